//! `asperity render IN -o OUT.png`: a picture of a mesh from the software rasteriser.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use serde_json::json;

use super::Context;
use crate::error::Result;
use crate::render::{RenderRequest, render};
use crate::request::Spelling;

/// The subcommand's flags (`RenderArgs`): the input, the output and the library's request.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Input mesh (.obj, .ply, .off, .stl, .glb, .gltf).
    input: PathBuf,
    /// Output picture (.png).
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    render: RenderRequest,
    #[command(flatten)]
    repair: super::input::RepairArg,
}

/// Runs the subcommand.
pub fn run(args: RenderArgs, ctx: Context) -> Result<()> {
    let start = Instant::now();
    super::require_extension(&args.output, &["png"])?;
    let options = args.render.options(Spelling::Flag)?;
    let input = super::input::read_input(&args.input, args.repair, ctx)?;
    let mesh = &input.read.mesh;
    let picture = ctx.spin("render", &args.input.display().to_string(), || render(mesh, &options))?;
    picture.write_png(&args.output)?;
    ctx.report(
        || {
            format!(
                "render: {} ({} tris, {}) => {} {}x{} in {} ms",
                args.input.display(),
                mesh.face_count(),
                format!("{:?}", options.mode).to_lowercase(),
                args.output.display(),
                picture.width,
                picture.height,
                super::millis(start)
            )
        },
        || {
            json!({
                "input": args.input, "output": args.output, "triangles": mesh.face_count(),
                "width": picture.width, "height": picture.height, "mode": options.mode, "repair": input.repair_json(),
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
