//! `asperity info FILE [--json]`: the validation report.

use std::path::PathBuf;

use clap::Args;
use serde::Serialize;

use crate::error::Result;
use crate::mesh::ValidationReport;

#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Mesh file (.obj, .ply, .off, .stl).
    file: PathBuf,
    #[command(flatten)]
    repair: super::input::RepairArg,
}

#[derive(Serialize)]
struct InfoReport<'a> {
    file: String,
    #[serde(flatten)]
    report: &'a ValidationReport,
    triangulated_polygons: usize,
    notes: &'a [String],
    repair: Option<crate::mesh::RepairReport>,
}

pub fn run(args: InfoArgs, ctx: super::Context) -> Result<()> {
    let input = super::input::read_input(&args.file, args.repair, ctx)?;
    let outcome = &input.read;
    let report = outcome.mesh.validate();
    if ctx.json {
        let full = InfoReport {
            file: args.file.display().to_string(),
            report: &report,
            triangulated_polygons: outcome.triangulated_polygons,
            notes: &outcome.notes,
            repair: input.repair,
        };
        println!("{}", serde_json::to_string_pretty(&full).expect("report serialises"));
        return Ok(());
    }
    if ctx.quiet {
        return Ok(());
    }
    let r = &report;
    println!("{}", args.file.display());
    println!("  vertices               {}", r.vertices);
    println!("  faces                  {}", r.faces);
    println!("  edges                  {}", r.edges);
    println!("  boundary loops         {}", r.boundary_loops);
    println!("  non-manifold edges     {}", r.non_manifold_edges);
    println!("  non-manifold vertices  {}", r.non_manifold_vertices);
    println!("  inconsistent edges     {}", r.inconsistently_oriented_edges);
    println!("  components             {}", r.components);
    println!("  euler characteristic   {}", r.euler);
    println!("  orientable             {}", if r.orientable { "yes" } else { "no" });
    let no_genus = if r.orientable { "n/a (not a manifold)" } else { "n/a (not orientable)" };
    println!("  genus                  {}", r.genus.map_or(no_genus.to_string(), |g| g.to_string()));
    println!("  degenerate faces       {}", r.degenerate_faces);
    println!("  unreferenced vertices  {}", r.unreferenced_vertices);
    println!("  triangulated polygons  {}", outcome.triangulated_polygons);
    println!("  bounding box           {:?} .. {:?}", r.bbox_min, r.bbox_max);
    Ok(())
}
