//! asperity for C++: the pipeline (simplify, detail with a recipe, terrain) over flat
//! arrays, exported through `cxx`. C++ programs include `asperity/pipeline.hpp`, which
//! wraps these functions for OpenMesh `TriMesh`es; errors arrive as `rust::Error`
//! exceptions carrying asperity's one-line message. Nothing here panics across the FFI:
//! every call is caught and turned into an error.

use arrays::{from_flat, to_flat};
use asperity::detail::{DetailOptions, Recipe};
use asperity::hierarchy::{KeepFeatures, SimplifyOptions, build};
use asperity::terrain::{Method, Rect, TerrainParams};
use asperity::{Error, Mesh};

#[cxx::bridge(namespace = "asperity::ffi")]
mod bridge {
    /// A triangle mesh as flat arrays: x y z per vertex, three vertex ids per triangle.
    #[derive(Debug, Default)]
    struct MeshArrays {
        positions: Vec<f64>,
        triangles: Vec<u32>,
    }

    /// What a pipeline call did.
    #[derive(Debug, Default)]
    struct Report {
        input_vertices: usize,
        output_vertices: usize,
        levels: usize,
        seconds: f64,
    }

    /// A result mesh with its report.
    #[derive(Debug, Default)]
    struct Outcome {
        mesh: MeshArrays,
        report: Report,
    }

    extern "Rust" {
        /// asperity's version.
        fn version() -> String;
        /// The base domain of the 4-k hierarchy with at most `target_vertices` vertices
        /// (feature vertices kept: "none", "strong" or "all").
        fn simplify(
            positions: &[f64],
            triangles: &[u32],
            target_vertices: usize,
            keep_features: &str,
        ) -> Result<Outcome>;
        /// The mesh with a detail recipe (TOML text, see docs/recipes.md) applied through
        /// the hierarchy, refined back to full resolution.
        fn detail(
            positions: &[f64],
            triangles: &[u32],
            recipe_toml: &str,
            no_self_intersections: bool,
        ) -> Result<Outcome>;
        /// A classic ("classic") or smoothed ("smooth") diamond-square terrain of size² points.
        fn terrain(method: &str, size: u64, hurst: f64, seed: u64) -> Result<Outcome>;
    }
}

use bridge::{MeshArrays, Outcome, Report};

fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

/// Runs `f`, turning panics into errors so that none unwinds into C++.
fn guarded<T>(f: impl FnOnce() -> asperity::Result<T>) -> Result<T, String> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(Ok(value)) => Ok(value),
        Ok(Err(e)) => Err(e.to_string()),
        Err(_) => Err("asperity: internal error (a bug: please report it)".into()),
    }
}

fn outcome(mesh: &Mesh, report: Report) -> Outcome {
    let (positions, triangles) = to_flat(mesh);
    Outcome { mesh: MeshArrays { positions, triangles }, report }
}

fn simplify(
    positions: &[f64],
    triangles: &[u32],
    target_vertices: usize,
    keep_features: &str,
) -> Result<Outcome, String> {
    guarded(|| {
        let start = std::time::Instant::now();
        let mesh = from_flat(positions, triangles)?;
        let keep_features = match keep_features {
            "none" => KeepFeatures::None,
            "strong" => KeepFeatures::Strong,
            "all" => KeepFeatures::All,
            other => return Err(Error::InvalidInput(format!("keep_features `{other}`: use none, strong or all"))),
        };
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

fn detail(
    positions: &[f64],
    triangles: &[u32],
    recipe_toml: &str,
    no_self_intersections: bool,
) -> Result<Outcome, String> {
    guarded(|| {
        let start = std::time::Instant::now();
        let mesh = from_flat(positions, triangles)?;
        let recipe = Recipe::parse(recipe_toml).map_err(|(line, message)| {
            Error::InvalidInput(match line {
                Some(line) => format!("recipe line {line}: {message}"),
                None => format!("recipe: {message}"),
            })
        })?;
        let target = recipe
            .hierarchy
            .target_vertices
            .as_deref()
            .map(|t| asperity::cli::resolve_target(t, mesh.vertex_count()))
            .transpose()?;
        let simplify = SimplifyOptions { target_vertices: target, ..Default::default() };
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

fn terrain(method: &str, size: u64, hurst: f64, seed: u64) -> Result<Outcome, String> {
    guarded(|| {
        let start = std::time::Instant::now();
        let method = match method {
            "classic" => Method::Classic,
            "smooth" => Method::Smooth,
            other => return Err(Error::InvalidInput(format!("terrain method `{other}`: use classic or smooth"))),
        };
        let params = TerrainParams { method, size, hurst, seed, ..TerrainParams::default() };
        params.generator()?;
        let last = size - 1;
        let mesh = asperity::terrain::mesh(&params, Rect { x0: 0, y0: 0, x1: last, y1: last })?;
        let report = Report {
            input_vertices: 0,
            output_vertices: mesh.vertex_count(),
            levels: 0,
            seconds: start.elapsed().as_secs_f64(),
        };
        Ok(outcome(&mesh, report))
    })
}

/// Flat arrays to and from [`Mesh`].
mod arrays {
    use asperity::{Error, Mesh, Result};

    pub fn from_flat(positions: &[f64], triangles: &[u32]) -> Result<Mesh> {
        if positions.len() % 3 != 0 || triangles.len() % 3 != 0 {
            return Err(Error::InvalidInput(format!(
                "{} coordinates and {} triangle ids are not multiples of 3",
                positions.len(),
                triangles.len()
            )));
        }
        let points = positions.chunks_exact(3).map(|p| glam::DVec3::new(p[0], p[1], p[2])).collect();
        let faces = triangles.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        let mesh = Mesh::new(points, faces);
        mesh.check()?;
        Ok(mesh)
    }

    pub fn to_flat(mesh: &Mesh) -> (Vec<f64>, Vec<u32>) {
        let positions = mesh.positions.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
        let triangles = mesh.triangles.iter().flatten().copied().collect();
        (positions, triangles)
    }
}
