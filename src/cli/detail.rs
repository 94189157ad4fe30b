//! `asperity detail IN [--recipe R.toml] -o OUT`: builds the 4-k hierarchy and refines it
//! back to full resolution, applying the recipe's steps at their levels. Without a recipe
//! this is the round trip, which must give back the input.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use serde_json::json;

use crate::detail::{DetailOptions, Recipe, apply_to};
use crate::error::{Error, Result};
use crate::hierarchy::{HierarchyRequest, build, connectivity_match};
use crate::io::{self, WriteOptions};
use crate::mesh::{Mesh, primitives};
use crate::request::Spelling;

/// The subcommand's flags (`DetailArgs`).
#[derive(Debug, Args)]
pub struct DetailArgs {
    /// Input mesh, or `builtin:sphere` (icosphere, 10 242 vertices) or `builtin:torus`.
    input: PathBuf,
    /// Output mesh (format by extension).
    #[arg(short, long)]
    output: PathBuf,
    /// Recipe (TOML, see docs/recipes.md); without one, the round trip.
    #[arg(long)]
    recipe: Option<PathBuf>,
    /// Keep the recipe's displacements even where the result intersects itself (by default
    /// the offending displacements are damped until there is no self-intersection).
    #[arg(long)]
    allow_self_intersections: bool,
    #[command(flatten)]
    hierarchy: HierarchyRequest,
    /// Test each level's new faces for self-intersections even where the recipe's hierarchy
    /// table turns the test off (intersection_guard = false).
    #[arg(long = "intersection-guard", conflicts_with = "intersection_guard")]
    intersection_guard_on: bool,
    /// Allow the output to overwrite the input.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    repair: super::input::RepairArg,
}

/// Runs the subcommand.
pub fn run(args: DetailArgs, ctx: super::Context) -> Result<()> {
    let start = Instant::now();
    io::Format::from_path(&args.output)?;
    super::guard_overwrite(&args.input, &args.output, args.force)?;
    let recipe = match &args.recipe {
        Some(path) => Recipe::read(path)?,
        None => Recipe::default(),
    };
    let (mesh, repair) = mesh_or_builtin(&args.input, args.repair, ctx)?;
    let mut request = args.hierarchy.clone();
    if args.intersection_guard_on {
        request.intersection_guard = Some(true);
    }
    let simplify = request.options_over(&recipe.hierarchy, mesh.vertex_count(), false, Spelling::Flag)?;
    let hierarchy = ctx
        .spin("simplify", "building the 4-k hierarchy", || build(&mesh, &simplify))
        .map_err(|e| super::input::after_repair(e, args.repair).about_file(&args.input))?;
    let options =
        DetailOptions { simplify, no_self_intersections: !args.allow_self_intersections, ..Default::default() };
    let mut outcome =
        ctx.spin("detail", "applying the recipe level by level", || apply_to(&hierarchy, &mesh, &recipe, &options))?;
    crate::io::obj::relocate_material_libraries(&mut outcome.result.mesh, &args.input, &args.output);
    io::write(&outcome.result.mesh, &args.output, WriteOptions::default())?;
    for note in &outcome.attribute_notes {
        ctx.note(note);
    }
    let exact = outcome.result.has_input_positions(&mesh);
    let matched = connectivity_match(&mesh.triangles, &outcome.result.triangles_in_ids());
    let seconds = json!({
        "hierarchy": hierarchy.seconds,
        "detail": outcome.seconds.detail,
        "refine": outcome.seconds.refine,
        "self_intersections": outcome.seconds.intersections,
    });
    if ctx.json {
        let report = json!({
            "input": args.input.display().to_string(),
            "output": args.output.display().to_string(),
            "recipe": args.recipe.as_ref().map(|p| p.display().to_string()),
            "input_vertices": mesh.vertex_count(),
            "base_vertices": outcome.base_vertices,
            "output_vertices": outcome.result.mesh.vertex_count(),
            "levels": outcome.levels,
            "positions_exact": exact,
            "faces_matched": matched,
            "steps": outcome.steps,
            "repair": repair,
            "self_intersections": outcome.intersections,
            "attribute_notes": outcome.attribute_notes,
            "seconds": seconds,
        });
        println!("{}", serde_json::to_string_pretty(&report).expect("report serialises"));
        return Ok(());
    }
    if ctx.quiet {
        return Ok(());
    }
    for s in &outcome.steps {
        println!(
            "step {}: {} at level {} ({} vertices): {} selected, {} touched in {:.0} ms",
            s.step,
            s.op,
            s.level,
            s.level_vertices,
            s.selected,
            s.touched,
            s.seconds * 1e3
        );
    }
    let i = outcome.intersections;
    let intersections = if !args.allow_self_intersections && i.found > 0 {
        format!("{} self-intersections, {} damped to {} in {} passes", i.found, i.damped, i.remaining, i.passes)
    } else {
        format!("{} self-intersections", i.found)
    };
    let shape = if recipe.steps.is_empty() {
        format!("positions {}, {:.2}% faces restored", if exact { "exact" } else { "moved" }, matched * 100.0)
    } else {
        format!("{} steps", recipe.steps.len())
    };
    println!(
        "detail: {} vertices => base {} => {} vertices over {} levels ({shape}; {intersections}) in {} ms",
        mesh.vertex_count(),
        outcome.base_vertices,
        outcome.result.mesh.vertex_count(),
        outcome.levels,
        super::millis(start)
    );
    Ok(())
}

/// The input of `detail` and `refine`: a built-in surface, or the file read (and repaired
/// when asked), with what the repair did.
///
/// # Errors
/// As [`builtin_mesh`] and [`super::input::read_input`].
pub fn mesh_or_builtin(
    input: &std::path::Path,
    repair: super::input::RepairArg,
    ctx: super::Context,
) -> Result<(Mesh, Option<crate::mesh::RepairReport>)> {
    match builtin_mesh(input)? {
        Some(mesh) => Ok((mesh, None)),
        None => {
            let read = super::input::read_input(input, repair, ctx)?;
            Ok((read.read.mesh, read.repair))
        }
    }
}

/// The surfaces made in code that recipes can run on (`builtin:NAME`), `None` for a path.
///
/// # Errors
/// [`Error::InvalidInput`] for an unknown built-in name.
pub fn builtin_mesh(input: &std::path::Path) -> Result<Option<Mesh>> {
    let Some(name) = input.to_str().and_then(|s| s.strip_prefix("builtin:")) else {
        return Ok(None);
    };
    match name {
        "sphere" => Ok(Some(primitives::icosphere(1.0, 5))),
        "torus" => Ok(Some(primitives::torus(1.0, 0.35, 96, 48))),
        _ => Err(Error::InvalidInput(format!("unknown built-in mesh '{name}' (use builtin:sphere or builtin:torus)"))),
    }
}
