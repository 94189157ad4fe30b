//! `asperity water TERRAIN --level Z -o OUT`: a wavy water surface over a terrain with a
//! depth attribute, one mesh per frame.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::{Error, Result};
use crate::scene::water::{WaterParams, opacity, surface_on, water_floor, waves_from_seed};

/// The most water vertices written over all frames.
const MAX_VERTICES: usize = 1 << 25;

/// The subcommand's flags.
#[derive(Debug, Args)]
pub struct WaterArgs {
    /// Terrain mesh, z up (.obj, .ply, .off, .stl, .glb, .gltf).
    input: PathBuf,
    /// Sea level (z, in the terrain's units).
    #[arg(long, allow_negative_numbers = true)]
    level: f64,
    /// Grid cells along the terrain's longer side.
    #[arg(long, default_value_t = 128)]
    cells: usize,
    /// Directional waves summed.
    #[arg(long, default_value_t = 4)]
    waves: usize,
    /// Seed of the waves' directions, lengths and phases.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Depth at which the water's opacity has risen by 1 − 1/e, as a fraction of the
    /// terrain's larger side.
    #[arg(long, default_value_t = 0.02)]
    clarity: f64,
    /// Frames written.
    #[arg(long, default_value_t = 24)]
    frames: usize,
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
    if !(1..=1000).contains(&args.frames) || args.waves > 64 {
        return Err(Error::InvalidInput("water: 1 to 1000 frames and at most 64 waves".into()));
    }
    let terrain = crate::io::read(&args.input)?.mesh;
    let (lo, hi) = terrain
        .bounding_box()
        .ok_or_else(|| Error::InvalidInput(format!("{}: the terrain has no vertices", args.input.display())))?;
    let extent = (hi - lo).truncate().max_element();
    let params = WaterParams {
        level: args.level,
        cells: args.cells,
        waves: waves_from_seed(args.seed, args.waves, extent),
        clarity: args.clarity * extent,
    };
    let floor = water_floor(&terrain, &params).map_err(|e| e.about_file(&args.input))?;
    let vertices = floor.point_count() * args.frames;
    if vertices > MAX_VERTICES {
        return Err(Error::InvalidInput(format!(
            "water: {} frames of {} vertices exceed {MAX_VERTICES} vertices: lower --cells or --frames",
            args.frames,
            floor.point_count()
        )));
    }
    let frames: Vec<_> = (0..args.frames).map(|k| surface_on(&floor, &params, k as f64 / fps)).collect();
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
                args.level,
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
