//! `asperity scene --seed S -o scene.glb [--preview scene.png]`: seed 002's whole
//! environment as one animated glTF scene.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::scene::compose::{SceneParams, compose};

/// The subcommand's flags: the scene's parameters and where it goes.
#[derive(Debug, Args)]
pub struct SceneArgs {
    #[command(flatten)]
    params: SceneParams,
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
    let params = args.params;
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
                params.seed,
                params.terrain_size,
                scene.sea_level,
                scene.placements.len(),
                scene.flights.len(),
                params.frames,
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
