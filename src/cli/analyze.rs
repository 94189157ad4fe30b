//! `asperity analyze IN -o OUT.ply [--json]`: curvatures and feature classes.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use serde_json::json;

use crate::analysis::{AnalysisOptions, FeatureOptions, NormalWeighting, analyze};
use crate::error::Result;
use crate::io::{self, WriteOptions};

/// The subcommand's flags (`AnalyzeArgs`).
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// Input mesh.
    input: PathBuf,
    /// Output mesh (PLY keeps every property; other formats keep what they can).
    #[arg(short, long)]
    output: PathBuf,
    /// Vertex normal weights.
    #[arg(long, value_enum, default_value_t = NormalWeighting::Angle)]
    normals: NormalWeighting,
    /// Corner when the normalised λ3 exceeds this.
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    corner: f64,
    /// Face vertex when λ2 is below this.
    #[arg(long, default_value_t = 0.02, allow_negative_numbers = true)]
    face: f64,
    /// Strong edge when λ2 exceeds this.
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    strong: f64,
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

impl AnalyzeArgs {
    /// The library options the flags give.
    pub fn options(&self) -> AnalysisOptions {
        AnalysisOptions {
            normal_weighting: self.normals,
            features: FeatureOptions {
                corner_min_l3: self.corner,
                face_max_l2: self.face,
                strong_min_l2: self.strong,
                ..FeatureOptions::default()
            },
        }
    }

    /// Whether `--repair` was given.
    pub fn repair(&self) -> bool {
        self.repair.repair
    }
}

/// Runs the subcommand.
pub fn run(args: AnalyzeArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    super::refuse_ascii_for(&args.output, args.ascii)?;
    super::guard_overwrite(&args.input, &args.output, args.force)?;
    let input = super::input::read_input(&args.input, args.repair, ctx)?;
    let mut mesh = input.read.mesh.clone();
    let options = args.options();
    let analysis = analyze(&mesh, &options)?;
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
