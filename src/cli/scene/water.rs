//! `asperity water TERRAIN --level Z -o OUT`: a wavy water surface over a terrain with a
//! depth attribute, one mesh per frame.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::scene::water::{WaterRequest, opacity};

/// The subcommand's flags: the terrain, the water's request and where the frames go.
#[derive(Debug, Args)]
pub struct WaterArgs {
    /// Terrain mesh, z up (.obj, .ply, .off, .stl, .glb, .gltf).
    input: PathBuf,
    #[command(flatten)]
    water: WaterRequest,
    /// Frames per second (the waves' time step, and the .glb animation's rate).
    #[arg(long)]
    fps: Option<f64>,
    /// Output: an animated .glb, or a mesh format (one file per frame; PLY keeps `depth`).
    #[arg(short, long)]
    output: PathBuf,
    /// Write text PLY/STL instead of binary.
    #[arg(long)]
    ascii: bool,
}

/// Runs the subcommand.
pub fn run(args: WaterArgs, ctx: super::super::Context) -> Result<()> {
    let start = Instant::now();
    super::super::refuse_ascii_for(&args.output, args.ascii)?;
    let fps = super::checked_fps(args.fps)?;
    args.water.check()?;
    let terrain = crate::io::read(&args.input)?.mesh;
    let (params, frames) = args.water.frames_over(&terrain, fps).map_err(|e| e.about_file(&args.input))?;
    let clarity = params.clarity;
    let opacity = |m: &crate::mesh::Mesh| m.scalars["depth"].iter().map(|&d| opacity(d, clarity) as f32).collect();
    let written = super::write_frames(&frames, "water", &args.output, fps, args.ascii, Some(&opacity))?;
    let depth = &frames[0].scalars["depth"];
    let wet = depth.iter().filter(|&&d| d > 0.0).count() as f64 / depth.len() as f64;
    ctx.report(
        || {
            format!(
                "water: {} at level {} => {} frames of {} vertices, {:.0}% over water => {} file(s) from {} in {} ms",
                args.input.display(),
                args.water.level,
                frames.len(),
                frames[0].vertex_count(),
                wet * 100.0,
                written.len(),
                written[0].display(),
                super::super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "input": args.input, "outputs": written, "frames": frames.len(), "vertices": frames[0].vertex_count(),
                "wet_share": wet, "waves": params.waves, "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
