//! The one-call pipeline: simplify to the base domain, detail with a recipe.

use asperity::detail::{DetailOptions, Recipe};
use asperity::hierarchy::{HierarchyRequest, VertexTarget, build};
use asperity::request::Spelling;
use asperity::{Error, Mesh};

use crate::arrays::{arrays_of, mesh_of};
use crate::bridge::{Outcome, RepairOutcome, Report};
use crate::guarded;

pub fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

/// A named setting of an option struct (`keep_features = "strong"`) read as the library's
/// request reads it, a wrong name refused as `option .field`.
pub fn named<T: serde::de::DeserializeOwned>(field: &str, text: &str) -> asperity::Result<T> {
    serde_json::from_value(serde_json::Value::String(text.to_string()))
        .map_err(|e| Error::InvalidInput(format!("{}: {e}", Spelling::Member.with(field, format!("\"{text}\"")))))
}

/// A vertex count of an option struct, checked as the library's request checks it.
pub fn target_of(count: usize) -> asperity::Result<VertexTarget> {
    VertexTarget::parse(&count.to_string())
        .map_err(|e| Error::InvalidInput(format!("{}: {e}", Spelling::Member.of("target_vertices"))))
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
        let request = HierarchyRequest {
            target_vertices: Some(target_of(target_vertices)?),
            keep_features: Some(named("keep_features", keep_features)?),
            ..HierarchyRequest::default()
        };
        let options = request.options(mesh.vertex_count(), false, Spelling::Member)?;
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
    hierarchy_fields: &str,
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
        // The caller's settings over the recipe's whole [hierarchy] table, through the one
        // function every front end applies it with (#36: only target_vertices was read
        // here; #38: the settings one by one, as the command line's flags).
        let over: HierarchyRequest = asperity::request::from_fields(hierarchy_fields, Spelling::Member)?;
        let simplify = over.options_over(
            &recipe.hierarchy,
            mesh.vertex_count(),
            false,
            Spelling::Member,
        )?;
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
