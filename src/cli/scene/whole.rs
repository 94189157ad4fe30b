//! `asperity scene --seed S -o scene.glb [--preview scene.png]`: seed 002's whole
//! environment as one animated glTF scene.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::scene::compose::{SceneParams, compose};

/// The subcommand's flags.
#[derive(Debug, Args)]
pub struct SceneArgs {
    /// Seed of everything.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Terrain grid points per side, 2^n + 1.
    #[arg(long, default_value_t = SceneParams::default().terrain_size)]
    size: u64,
    /// Share of the terrain under the sea (0 to 1).
    #[arg(long, default_value_t = SceneParams::default().sea_fraction)]
    sea_fraction: f64,
    /// Trees wanted.
    #[arg(long, default_value_t = SceneParams::default().trees)]
    trees: usize,
    /// Steepest ground a tree stands on, degrees.
    #[arg(long, default_value_t = SceneParams::default().max_slope_deg)]
    max_slope: f64,
    /// Butterflies.
    #[arg(long, default_value_t = SceneParams::default().butterflies)]
    butterflies: usize,
    /// Animation frames.
    #[arg(long, default_value_t = SceneParams::default().frames)]
    frames: usize,
    /// Frames per second.
    #[arg(long, default_value_t = SceneParams::default().fps)]
    fps: f64,
    /// Output .glb.
    #[arg(short, long)]
    output: PathBuf,
    /// Also draw frame 0 as a PNG, with the water's Fresnel effect.
    #[arg(long)]
    preview: Option<PathBuf>,
}

/// Runs the subcommand.
pub fn run(args: SceneArgs, ctx: super::super::Context) -> Result<()> {
    let start = Instant::now();
    super::super::require_extension(&args.output, &["glb"])?;
    if let Some(preview) = &args.preview {
        super::super::require_extension(preview, &["png"])?;
    }
    let params = SceneParams {
        seed: args.seed,
        terrain_size: args.size,
        sea_fraction: args.sea_fraction,
        trees: args.trees,
        max_slope_deg: args.max_slope,
        butterflies: args.butterflies,
        frames: args.frames,
        fps: args.fps,
        ..SceneParams::default()
    };
    let scene = compose(&params)?;
    let doc = scene.glb();
    crate::io::glb_scene::write_scene_glb(&doc, &args.output)?;
    if let Some(preview) = &args.preview {
        crate::render::render(&scene.still(), &scene.preview_options(1200, 800))?.write_png(preview)?;
    }
    let triangles: usize = doc.meshes.iter().map(|m| m.mesh.face_count()).sum();
    ctx.report(
        || {
            format!(
                "scene: seed {} => terrain {}², sea level {:.2} m, {} plants, cabin, smoke, {} butterflies, {} frames ({} meshes, {} tris) => {}{} in {} ms",
                args.seed,
                args.size,
                scene.sea_level,
                scene.placements.len(),
                scene.flights.len(),
                args.frames,
                doc.meshes.len(),
                triangles,
                args.output.display(),
                args.preview.as_ref().map_or(String::new(), |p| format!(" and {}", p.display())),
                super::super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "output": args.output, "preview": args.preview, "params": params, "sea_level": scene.sea_level,
                "plants": scene.placements.len(), "butterflies": scene.flights.len(), "meshes": doc.meshes.len(),
                "nodes": doc.nodes.len(), "tracks": doc.tracks.len(), "triangles": triangles,
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
