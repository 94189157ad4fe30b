//! `asperity detail IN -o OUT`: builds the 4-k hierarchy and refines it back to full
//! resolution. Without a recipe this is the round trip, which must give back the input.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use serde_json::json;

use super::simplify::HierarchyArgs;
use crate::error::Result;
use crate::hierarchy::{Refiner, build, connectivity_match};
use crate::io::{self, WriteOptions};

#[derive(Debug, Args)]
pub struct DetailArgs {
    /// Input mesh.
    input: PathBuf,
    /// Output mesh (format by extension).
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    hierarchy: HierarchyArgs,
    /// Print a JSON report.
    #[arg(long)]
    json: bool,
    /// Allow the output to overwrite the input.
    #[arg(long)]
    force: bool,
}

pub fn run(args: DetailArgs) -> Result<()> {
    let start = Instant::now();
    io::Format::from_path(&args.output)?;
    super::guard_overwrite(&args.input, &args.output, args.force)?;
    let mesh = io::read(&args.input)?.mesh;
    let hierarchy = build(&mesh, &args.hierarchy.options(mesh.vertex_count(), false)?)?;
    let refine_start = Instant::now();
    let mut refiner = Refiner::new(&hierarchy)?;
    let reports = refiner.refine_all()?;
    let refined = refiner.mesh()?;
    let refine_seconds = refine_start.elapsed().as_secs_f64();
    io::write(&refined.mesh, &args.output, WriteOptions::default())?;
    let exact = refined.has_input_positions(&mesh);
    let matched = connectivity_match(&mesh.triangles, &refined.triangles_in_ids());
    let relocated: usize = reports.iter().map(|r| r.relocated).sum();
    if args.json {
        let report = json!({
            "input": args.input.display().to_string(),
            "output": args.output.display().to_string(),
            "input_vertices": mesh.vertex_count(),
            "base_vertices": hierarchy.base_vertex_count(),
            "output_vertices": refined.mesh.vertex_count(),
            "levels": hierarchy.steps(),
            "positions_exact": exact,
            "faces_matched": matched,
            "relocated": relocated,
            "build_seconds": hierarchy.seconds,
            "refine_seconds": refine_seconds,
            "levels_report": reports,
        });
        println!("{}", serde_json::to_string_pretty(&report).expect("report serialises"));
    } else {
        println!(
            "detail: {} vertices => base {} => {} vertices over {} levels (positions {}, {:.2}% faces restored) in {} ms",
            mesh.vertex_count(),
            hierarchy.base_vertex_count(),
            refined.mesh.vertex_count(),
            hierarchy.steps(),
            if exact { "exact" } else { "moved" },
            matched * 100.0,
            super::millis(start)
        );
    }
    Ok(())
}
