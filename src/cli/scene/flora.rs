//! `asperity flora (--preset P | --rules FILE) --seed S -o OUT`: one plant from a
//! stochastic L-system.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;

use crate::error::Result;
use crate::io::WriteOptions;
use crate::scene::flora::{FloraPreset, FloraRules, plant};

/// The subcommand's flags.
#[derive(Debug, Args)]
pub struct FloraArgs {
    /// A preset from seed 002: a cottonwood-like tree, a palm (a chain) or a flower.
    #[arg(long, required_unless_present = "rules", conflicts_with = "rules")]
    preset: Option<FloraPreset>,
    /// Rules as TOML (the presets' format: src/scene/flora/*.toml).
    #[arg(long)]
    rules: Option<PathBuf>,
    /// Seed of the productions and annotations.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Vertices around each branch ring (3 to 64).
    #[arg(long, default_value_t = 8)]
    sides: u32,
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
    let rules = match (&args.rules, args.preset) {
        (Some(path), _) => FloraRules::read(path)?,
        (None, Some(preset)) => preset.rules(),
        (None, None) => unreachable!("clap requires one"),
    };
    let grown = plant(&rules, args.seed, args.sides)?;
    let mesh = grown.mesh();
    crate::io::write(&mesh, &args.output, WriteOptions { ascii: args.ascii })?;
    let leaves = grown.nodes.iter().filter(|n| n.children.is_empty()).count();
    let source = args
        .rules
        .as_ref()
        .map_or_else(|| format!("{:?}", args.preset.expect("a preset")).to_lowercase(), |p| p.display().to_string());
    ctx.report(
        || {
            format!(
                "flora: {source} seed {} => {} nodes ({} leaf clusters) => {} vertices, {} tris => {} in {} ms",
                args.seed,
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
                "output": args.output, "rules": source, "seed": args.seed, "nodes": grown.nodes.len(),
                "leaf_nodes": leaves, "vertices": mesh.vertex_count(), "triangles": mesh.face_count(),
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
