//! `asperity smoke --frames N -o OUT`: the smoke plume, one metaball surface per frame.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::scene::smoke::{SmokeParams, smoke_frames};

/// The subcommand's flags: the plume's parameters, the frames and where they go.
#[derive(Debug, Args)]
pub struct SmokeArgs {
    #[command(flatten)]
    params: SmokeParams,
    /// Frames written.
    #[arg(long, default_value_t = 24)]
    frames: usize,
    /// Steps before the first frame.
    #[arg(long, default_value_t = 40)]
    warmup: usize,
    /// Steps between frames.
    #[arg(long, default_value_t = 1)]
    steps_per_frame: usize,
    /// Frames per second of the .glb animation.
    #[arg(long)]
    fps: Option<f64>,
    /// Output: an animated .glb, or a mesh format (one file per frame, NAME_000.ply …).
    #[arg(short, long)]
    output: PathBuf,
    /// Write text PLY/STL instead of binary.
    #[arg(long)]
    ascii: bool,
}

/// Runs the subcommand.
pub fn run(args: SmokeArgs, ctx: super::super::Context) -> Result<()> {
    let start = Instant::now();
    super::super::refuse_ascii_for(&args.output, args.ascii)?;
    super::refuse_for_meshes(&args.output, "--fps", args.fps.is_some())?;
    let fps = super::checked_fps(args.fps)?;
    let frames = smoke_frames(args.params, args.warmup, args.steps_per_frame, args.frames)?;
    super::refuse_empty_frames(
        &frames,
        "smoke",
        "no particle is in the unit cube then (raise --warmup's batches or lower --rise)",
    )?;
    let written = super::write_frames(&frames, "smoke", &args.output, fps, args.ascii, None)?;
    let triangles: Vec<usize> = frames.iter().map(|m| m.face_count()).collect();
    ctx.report(
        || {
            format!(
                "smoke: {} frames, {} to {} tris => {} file(s) from {} in {} ms",
                frames.len(),
                triangles.iter().min().unwrap_or(&0),
                triangles.iter().max().unwrap_or(&0),
                written.len(),
                written[0].display(),
                super::super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "outputs": written, "frames": frames.len(), "triangles": triangles, "params": args.params,
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
