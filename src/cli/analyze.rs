//! `asperity analyze IN -o OUT.ply [--json]`: curvatures and feature classes.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use serde_json::json;

use crate::analysis::AnalysisRequest;
use crate::error::Result;
use crate::io::{self, WriteOptions};
use crate::request::Spelling;

/// The subcommand's flags (`AnalyzeArgs`).
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// Input mesh.
    input: PathBuf,
    /// Output mesh (PLY keeps every property; other formats keep what they can).
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    analysis: AnalysisRequest,
    /// Write text PLY.
    #[arg(long)]
    ascii: bool,
    /// Allow the output to overwrite the input.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    repair: super::input::RepairArg,
}

fn stats(values: &[f64]) -> serde_json::Value {
    let n = values.len().max(1) as f64;
    let mean = values.iter().sum::<f64>() / n;
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    json!({ "min": min, "max": max, "mean": mean })
}

/// Runs the subcommand.
pub fn run(args: AnalyzeArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    super::refuse_ascii_for(&args.output, args.ascii)?;
    super::guard_overwrite(&args.input, &args.output, args.force)?;
    let input = super::input::read_input(&args.input, args.repair, ctx)?;
    let mut mesh = input.read.mesh.clone();
    let analysis = args.analysis.analyze(&mesh, Spelling::Flag)?;
    analysis.attach_to(&mut mesh);
    io::write(&mesh, &args.output, WriteOptions { ascii: args.ascii })?;
    let [face, weak, strong, corner] = analysis.class_counts();
    if ctx.json {
        let c = &analysis.curvatures;
        let report = json!({
            "input": args.input.display().to_string(),
            "output": args.output.display().to_string(),
            "vertices": mesh.vertex_count(),
            "classes": { "face": face, "weak": weak, "strong_edge": strong, "corner": corner },
            "mean_curvature": stats(&c.mean),
            "gaussian_curvature": stats(&c.gaussian),
            "k1": stats(&c.k1),
            "k2": stats(&c.k2),
            "repair": input.repair_json(),
            "milliseconds": super::millis(start),
        });
        println!("{}", serde_json::to_string_pretty(&report).expect("report serialises"));
    } else if !ctx.quiet {
        println!(
            "analyze: {} ({} vertices) => {corner} corners, {strong} strong edge, {weak} weak, {face} face vertices => {} in {} ms",
            args.input.display(),
            mesh.vertex_count(),
            args.output.display(),
            super::millis(start)
        );
    }
    Ok(())
}
