//! `asperity compare IN --target-vertices V [--json]`: ours against OpenMesh, CGAL and
//! meshoptimizer, one line each, at the requested target and, where the counts differ,
//! again at the smallest count all reached (#34).

use std::path::PathBuf;

use clap::Args;

use crate::error::Result;
use crate::hierarchy::CompareRequest;
use crate::hierarchy::compare::CompareRow;
use crate::request::Spelling;

/// The subcommand's flags (`CompareArgs`): the input and the library's request.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Input mesh.
    input: PathBuf,
    #[command(flatten)]
    compare: CompareRequest,
    #[command(flatten)]
    repair: super::input::RepairArg,
}

/// Runs the subcommand.
pub fn run(args: CompareArgs, ctx: super::Context) -> Result<()> {
    let mesh = super::input::read_input(&args.input, args.repair, ctx)?.read.mesh;
    let report = ctx
        .spin("compare", &args.compare.methods.join(", "), || args.compare.report(&mesh, Spelling::Flag))
        .map_err(|e| super::input::after_repair(e, args.repair).about_file(&args.input))?;
    if ctx.json {
        println!("{}", serde_json::to_string_pretty(&report).expect("report serialises"));
    } else if !ctx.quiet {
        println!(
            "at the requested target ({} vertices; the input cuts itself at {} face pairs):",
            report.target_vertices, report.input_self_intersections
        );
        print_rows(&report.at_target, mesh.face_count(), true);
        if let Some(common) = &report.at_common_count {
            let short: Vec<&str> = report
                .at_target
                .iter()
                .filter(|r| !crate::hierarchy::compare::same_count(r.vertices, report.target_vertices))
                .map(|r| r.method.as_str())
                .collect();
            println!(
                "at {} vertices, the smallest count all reached (like with like; {} stopped short of {}):",
                common.vertices,
                short.join(", "),
                report.target_vertices
            );
            print_rows(&common.rows, mesh.face_count(), false);
        }
    }
    Ok(())
}

/// One line per method; with `notes`, what gave way in ours and why it stopped short.
fn print_rows(rows: &[CompareRow], input_faces: usize, notes: bool) {
    for r in rows {
        println!(
            "{:<13} {} tris => {} tris, {} vertices (hausdorff {:.3}%, rms {:.4}%, min angle {:.2}°, p1 angle {:.2}°, slivers {:.2}%, {} features kept, cuts itself at {} face pairs) in {:.0} ms",
            format!("{}:", r.method),
            input_faces,
            r.faces,
            r.vertices,
            r.hausdorff * 100.0,
            r.rms * 100.0,
            r.min_angle_deg,
            r.min_angle_p1_deg,
            r.sliver_share * 100.0,
            r.features_kept,
            r.self_intersections,
            r.seconds * 1e3
        );
        if !notes {
            continue;
        }
        if let Some(gave_way) = r.gave_way.as_deref().filter(|g| *g != "nothing") {
            println!("{:<13} gave way: {gave_way}", "");
        }
        if let Some(stopped_by) = &r.stopped_by {
            println!("note: {} stopped short of {} vertices: {stopped_by}", r.method, r.target_vertices);
        }
    }
}
