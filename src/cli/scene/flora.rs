//! `asperity flora (--preset P | --rules FILE) --seed S -o OUT`: one plant from a
//! stochastic L-system.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::io::WriteOptions;
use crate::scene::flora::FloraRequest;

/// The subcommand's flags: the plant's request and where it goes.
#[derive(Debug, Args)]
pub struct FloraArgs {
    #[command(flatten)]
    plant: FloraRequest,
    /// Output mesh; the format follows the extension.
    #[arg(short, long)]
    output: PathBuf,
    /// Write text PLY/STL instead of binary.
    #[arg(long)]
    ascii: bool,
}

/// Runs the subcommand.
pub fn run(args: FloraArgs, ctx: super::super::Context) -> Result<()> {
    let start = Instant::now();
    super::super::refuse_ascii_for(&args.output, args.ascii)?;
    let grown = args.plant.plant()?;
    let mesh = grown.mesh();
    crate::io::write(&mesh, &args.output, WriteOptions { ascii: args.ascii })?;
    let leaves = grown.nodes.iter().filter(|n| n.children.is_empty()).count();
    let source = args.plant.source();
    ctx.report(
        || {
            format!(
                "flora: {source} seed {} => {} nodes ({} leaf clusters) => {} vertices, {} tris => {} in {} ms",
                args.plant.seed,
                grown.nodes.len(),
                leaves,
                mesh.vertex_count(),
                mesh.face_count(),
                args.output.display(),
                super::super::millis(start)
            )
        },
        || {
            serde_json::json!({
                "output": args.output, "rules": source, "seed": args.plant.seed, "nodes": grown.nodes.len(),
                "leaf_nodes": leaves, "vertices": mesh.vertex_count(), "triangles": mesh.face_count(),
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
