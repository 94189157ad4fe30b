//! `asperity refine IN --region SEL [--base-level L] -o OUT`: region refinement (thesis
//! §4.6): the selected region at the input's resolution, the rest at level L.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use serde_json::json;

use crate::detail::{Selection, input_selection};
use crate::error::{Error, Result};
use crate::hierarchy::region::refine_region;
use crate::hierarchy::{HierarchyRequest, build};
use crate::io::{self, WriteOptions};
use crate::request::Spelling;

/// The subcommand's flags.
#[derive(Debug, Args)]
pub struct RefineArgs {
    /// Input mesh, or `builtin:sphere` or `builtin:torus`.
    input: PathBuf,
    /// Output mesh (format by extension).
    #[arg(short, long)]
    output: PathBuf,
    /// The region refined to full resolution, as a recipe's `select` (docs/recipes.md),
    /// e.g. 'sphere = { center = [0.5, 0.5, 1], radius = 0.3 }' or
    /// 'features = { classes = ["corner", "strong"], mode = "on", propagate = 2 }'.
    #[arg(long)]
    region: String,
    /// The level the rest stays at (0: the base domain).
    #[arg(long, default_value_t = 0)]
    base_level: usize,
    /// Seed of a selection's random parts (an independent set's shuffle).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    #[command(flatten)]
    hierarchy: HierarchyRequest,
    /// Allow the output to overwrite the input.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    repair: super::input::RepairArg,
}

/// Parses `--region`: a TOML inline table's contents.
fn parse_region(text: &str) -> Result<Selection> {
    toml::from_str::<Selection>(text).map_err(|e| {
        Error::InvalidInput(format!(
            "--region: {} (expected e.g. 'box = {{ min = [0, 0, 0.5], max = [1, 1, 1] }}')",
            e.message().trim()
        ))
    })
}

/// Runs the subcommand.
pub fn run(args: RefineArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    io::Format::from_path(&args.output)?;
    super::guard_overwrite(&args.input, &args.output, args.force)?;
    let selection = parse_region(&args.region)?;
    let (mesh, repair) = super::detail::mesh_or_builtin(&args.input, args.repair, ctx)?;
    let inside = input_selection(&mesh, &selection, args.seed).map_err(|e| e.about_file(&args.input))?;
    let options = args.hierarchy.options(mesh.vertex_count(), false, Spelling::Flag)?;
    let hierarchy = ctx
        .spin("simplify", "building the 4-k hierarchy", || build(&mesh, &options))
        .map_err(|e| super::input::after_repair(e, args.repair).about_file(&args.input))?;
    let mut refined = refine_region(&hierarchy, args.base_level, &|v| inside[v as usize])?;
    // The input's UVs and materials on the refined faces. A face whose wedge cannot be
    // found (Algorithm 2's search put a seam vertex off its seam) leaves them out, said.
    if let Err(e) = hierarchy.attach_attributes(&mut refined.mesh, &[]) {
        ctx.note(&format!("UVs and materials not carried: {e}"));
    }
    crate::io::obj::relocate_material_libraries(&mut refined.mesh.mesh, &args.input, &args.output);
    let out = &refined.mesh.mesh;
    io::write(out, &args.output, WriteOptions::default())?;
    let report = out.validate();
    let intersections = refined.self_intersections;
    let t = refined.totals();
    let region = inside.iter().filter(|&&i| i).count();
    let replayed = t.inserted - t.relocated;
    ctx.report(
        || {
            format!(
                "refine: {} ({} vertices, region {}) => {} vertices at levels {}..{}: {} replayed, {} by Algorithm 2's search ({} one ring further), {} flips ({} by Algorithm 3's widest angle), {} region vertices missing, genus {}, {} self-intersections ({} rounds) => {} in {} ms",
                args.input.display(),
                mesh.vertex_count(),
                region,
                out.vertex_count(),
                args.base_level,
                hierarchy.steps(),
                replayed,
                t.relocated,
                t.widened,
                t.flips,
                t.widest_flips,
                refined.missing.len(),
                report.genus.map_or("-".into(), |g| g.to_string()),
                intersections,
                refined.rounds,
                args.output.display(),
                super::millis(start)
            )
        },
        || {
            json!({
                "input": args.input, "output": args.output, "input_vertices": mesh.vertex_count(),
                "region_vertices": region, "output_vertices": out.vertex_count(), "base_level": args.base_level,
                "levels": hierarchy.steps(), "replayed": replayed, "searched": t.relocated, "widened": t.widened,
                "flips": t.flips, "widest_flips": t.widest_flips, "degree_misses": t.degree_misses,
                "missing": refined.missing, "genus": report.genus, "manifold": report.is_manifold(),
                "self_intersections": intersections, "rounds": refined.rounds, "repair": repair,
                "seconds": start.elapsed().as_secs_f64(),
            })
        },
    );
    Ok(())
}
