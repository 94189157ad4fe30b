//! The one-call pipeline: simplify to the base domain, detail with a recipe.

use asperity::detail::{DetailOptions, Recipe};
use asperity::hierarchy::{KeepFeatures, SimplifyOptions, build};
use asperity::{Error, Mesh};

use crate::arrays::{arrays_of, mesh_of};
use crate::bridge::{Outcome, RepairOutcome, Report};
use crate::guarded;

pub fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

/// A `keep_features` name.
pub fn keep_features_of(name: &str) -> asperity::Result<KeepFeatures> {
    match name {
        "none" => Ok(KeepFeatures::None),
        "corners" => Ok(KeepFeatures::Corners),
        "strong" => Ok(KeepFeatures::Strong),
        "all" => Ok(KeepFeatures::All),
        other => Err(Error::InvalidInput(format!("keep_features `{other}`: use none, corners, strong or all"))),
    }
}

fn outcome(mesh: &Mesh, report: Report) -> Outcome {
    let colors = mesh.colors.iter().flatten().flatten().copied().collect();
    Outcome { mesh: arrays_of(mesh), report, colors }
}

pub fn simplify(
    positions: &[f64],
    triangles: &[u32],
    target_vertices: usize,
    keep_features: &str,
) -> Result<Outcome, String> {
    guarded(|| {
        let start = std::time::Instant::now();
        let mesh = mesh_of(positions, triangles)?;
        let keep_features = keep_features_of(keep_features)?;
        let options = SimplifyOptions { target_vertices: Some(target_vertices), keep_features, ..Default::default() };
        let hierarchy = build(&mesh, &options)?;
        let base = hierarchy.base_mesh().mesh;
        let report = Report {
            input_vertices: mesh.vertex_count(),
            output_vertices: base.vertex_count(),
            levels: hierarchy.steps(),
            seconds: start.elapsed().as_secs_f64(),
        };
        Ok(outcome(&base, report))
    })
}

pub fn detail(
    positions: &[f64],
    triangles: &[u32],
    recipe_toml: &str,
    no_self_intersections: bool,
) -> Result<Outcome, String> {
    guarded(|| {
        let start = std::time::Instant::now();
        let mesh = mesh_of(positions, triangles)?;
        let recipe = Recipe::parse(recipe_toml).map_err(|(line, message)| {
            Error::InvalidInput(match line {
                Some(line) => format!("recipe line {line}: {message}"),
                None => format!("recipe: {message}"),
            })
        })?;
        // The recipe's whole [hierarchy] table, read as the command line reads it (#36: only
        // target_vertices was read here).
        let simplify = recipe.hierarchy.apply(SimplifyOptions::default(), mesh.vertex_count())?;
        let options = DetailOptions { simplify, no_self_intersections, ..Default::default() };
        let result = asperity::detail::apply(&mesh, &recipe, &options)?;
        let report = Report {
            input_vertices: mesh.vertex_count(),
            output_vertices: result.result.mesh.vertex_count(),
            levels: result.levels,
            seconds: start.elapsed().as_secs_f64(),
        };
        Ok(outcome(&result.result.mesh, report))
    })
}

pub fn repair(positions: &[f64], triangles: &[u32]) -> Result<RepairOutcome, String> {
    guarded(|| {
        let mesh = mesh_of(positions, triangles)?;
        let (repaired, report, origins) = asperity::mesh::repair_with_origins(&mesh)?;
        Ok(RepairOutcome { mesh: arrays_of(&repaired), source: origins.source, report: report.to_string() })
    })
}
