//! `asperity convert IN OUT [--ascii] [--force]`: mesh format conversion.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::io::{self, WriteOptions};

#[derive(Debug, Args)]
pub struct ConvertArgs {
    /// Input mesh (.obj, .ply, .off, .stl, .glb, .gltf).
    input: PathBuf,
    /// Output mesh; the format follows the extension.
    output: PathBuf,
    /// Write text PLY/STL instead of binary.
    #[arg(long)]
    ascii: bool,
    /// Allow the output to overwrite the input.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    repair: super::input::RepairArg,
}

pub fn run(args: ConvertArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    super::refuse_ascii_for(&args.output, args.ascii)?;
    super::guard_overwrite(&args.input, &args.output, args.force)?;
    let input = super::input::read_input(&args.input, args.repair, ctx)?;
    let outcome = &input.read;
    io::write(&outcome.mesh, &args.output, WriteOptions { ascii: args.ascii })
        .map_err(|e| e.about_file(&args.input))?;
    let m = &outcome.mesh;
    let polygons = match outcome.triangulated_polygons {
        0 => String::new(),
        n => format!(", {n} polygons triangulated"),
    };
    ctx.report(
        || {
            format!(
                "convert: {} ({} vertices, {} tris{polygons}) => {} in {} ms",
                args.input.display(),
                m.vertex_count(),
                m.face_count(),
                args.output.display(),
                super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "input": args.input, "output": args.output, "vertices": m.vertex_count(), "triangles": m.face_count(),
                "triangulated_polygons": outcome.triangulated_polygons, "notes": outcome.notes, "repair": input.repair_json(),
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
