//! `asperity smoke --frames N -o OUT`: the smoke plume, one metaball surface per frame.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::scene::smoke::{SmokeParams, smoke_frames};

/// The subcommand's flags.
#[derive(Debug, Args)]
pub struct SmokeArgs {
    /// Seed of the emission points and the vector field.
    #[arg(long, default_value_t = 0)]
    seed: u64,
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
    /// Particles per batch.
    #[arg(long, default_value_t = SmokeParams::default().batch)]
    batch: usize,
    /// Steps between batches.
    #[arg(long, default_value_t = SmokeParams::default().emit_every)]
    emit_every: usize,
    /// Time step of forward Euler.
    #[arg(long, default_value_t = SmokeParams::default().dt)]
    dt: f64,
    /// Cells of the random vector field per side.
    #[arg(long, default_value_t = SmokeParams::default().field_cells)]
    field_cells: usize,
    /// Largest sideways component of the field's vectors.
    #[arg(long, default_value_t = SmokeParams::default().swirl)]
    swirl: f64,
    /// The field's fixed upward component.
    #[arg(long, default_value_t = SmokeParams::default().rise)]
    rise: f64,
    /// Half-width of the emission square on the xy-plane, around (½, ½).
    #[arg(long, default_value_t = SmokeParams::default().spread)]
    spread: f64,
    /// Radius of one particle's blob.
    #[arg(long, default_value_t = SmokeParams::default().radius)]
    radius: f64,
    /// Blinn's blobbiness (larger: blobs merge less).
    #[arg(long, default_value_t = SmokeParams::default().blobbiness)]
    blobbiness: f64,
    /// Grid points per unit of the marching-tetrahedra grid.
    #[arg(long, default_value_t = SmokeParams::default().resolution)]
    resolution: usize,
    /// Output: an animated .glb, or a mesh format (one file per frame, NAME_000.ply …).
    #[arg(short, long)]
    output: PathBuf,
    /// Write text PLY/STL instead of binary.
    #[arg(long)]
    ascii: bool,
}

impl SmokeArgs {
    /// The library parameters the flags give.
    pub fn params(&self) -> SmokeParams {
        SmokeParams {
            seed: self.seed,
            batch: self.batch,
            emit_every: self.emit_every,
            dt: self.dt,
            field_cells: self.field_cells,
            swirl: self.swirl,
            rise: self.rise,
            spread: self.spread,
            radius: self.radius,
            blobbiness: self.blobbiness,
            resolution: self.resolution,
        }
    }
}

/// Runs the subcommand.
pub fn run(args: SmokeArgs, ctx: super::super::Context) -> Result<()> {
    let start = Instant::now();
    super::super::refuse_ascii_for(&args.output, args.ascii)?;
    super::refuse_for_meshes(&args.output, "--fps", args.fps.is_some())?;
    let fps = super::checked_fps(args.fps)?;
    let frames = smoke_frames(args.params(), args.warmup, args.steps_per_frame, args.frames)?;
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
                "outputs": written, "frames": frames.len(), "triangles": triangles, "params": args.params(),
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
