//! asperity for C++: the pipeline and the hierarchy over flat arrays, exported through
//! `cxx`. C++ programs include `asperity/asperity.hpp`, whose templates wrap these
//! functions for OpenMesh `TriMesh`es (see `cpp/package/`).
//!
//! Errors: every function returns `Result<_, String>`, the message prefixed with the
//! command line's exit code and a bar (`2|…` bad input, `1|…` internal), which the C++
//! side turns into `asperity::InputError` or `asperity::InternalError`. Nothing panics
//! across the FFI (every call is caught). The one call from Rust into C++ code the user
//! wrote is a progress function (`progress.rs`), and its C++ wrapper catches every
//! exception and rethrows it after the call; a C++ operator runs between calls (see
//! `hierarchy::Refinement`), so no C++ exception crosses into Rust.

mod arrays;
mod fields;
mod hierarchy;
mod measures;
mod pipeline;
mod progress;

use fields::{analyze, noise, terrain_mesh};
use hierarchy::{BuiltHierarchy, Refinement, build_hierarchy, default_hierarchy_options, start_refinement};
use measures::{hausdorff, triangulate, validate};
use pipeline::{detail, repair, simplify, version};

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

    /// A result mesh with its report, and vertex colours (r g b per vertex) where the
    /// result has them (a detail recipe's `[color]` table), else empty.
    #[derive(Debug, Default)]
    struct Outcome {
        mesh: MeshArrays,
        report: Report,
        colors: Vec<u8>,
    }

    /// A hierarchy level's mesh, or a refinement's: the input vertex id of each vertex, and
    /// when the input had texture coordinates, u v per face corner (6 per triangle).
    #[derive(Debug, Default)]
    struct LevelArrays {
        mesh: MeshArrays,
        ids: Vec<u32>,
        corner_uvs: Vec<f64>,
    }

    /// The options of a hierarchy build (the library's `SimplifyOptions`); a limit applies
    /// only when its `has_` flag is set.
    #[derive(Debug, Clone)]
    struct HierarchyOptions {
        has_target_vertices: bool,
        target_vertices: usize,
        has_levels: bool,
        levels: usize,
        has_max_error: bool,
        max_error: f64,
        keep_features: String,
        feature_vertices: String,
        keep_vertices: Vec<u32>,
        removal_weight: f64,
        swap_weight: f64,
        fix_threshold_degrees: f64,
        intersection_guard: bool,
        /// Parts of a partitioned build (#40); 0: one piece.
        chunks: usize,
    }

    /// The hierarchical parametrization, per input vertex: the level at which it appears
    /// (0: base domain), the index of its base face in level 0's triangles (−1 for base
    /// vertices) and its barycentric coordinates there (in that triangle's corner order;
    /// NaN for base vertices).
    #[derive(Debug, Default)]
    struct Parametrization {
        level: Vec<u32>,
        base_face: Vec<i64>,
        barycentric: Vec<f64>,
    }

    /// Surface analysis per vertex: unit normals (x y z), curvatures and feature classes
    /// (0 face, 1 weak, 2 strong edge, 3 corner).
    #[derive(Debug, Default)]
    struct Analysis {
        normals: Vec<f64>,
        mean_curvature: Vec<f64>,
        gaussian_curvature: Vec<f64>,
        k1: Vec<f64>,
        k2: Vec<f64>,
        feature_class: Vec<u8>,
    }

    /// What one refinement level shows an operator: the mesh, unit normals and the level
    /// at which each vertex first appears.
    #[derive(Debug, Default)]
    struct ViewArrays {
        level: LevelArrays,
        normals: Vec<f64>,
        vertex_levels: Vec<u32>,
    }

    /// A region refinement's result: the mesh, and the region vertices no edge could take.
    #[derive(Debug, Default)]
    struct RegionOutcome {
        level: LevelArrays,
        missing: Vec<u32>,
        report: Report,
    }

    /// A repaired mesh: its arrays, the input vertex each of its vertices is (a split copy:
    /// the vertex it copies), and what the repair did, as one line.
    #[derive(Debug, Default)]
    struct RepairOutcome {
        mesh: MeshArrays,
        source: Vec<u32>,
        report: String,
    }

    /// A terrain mesh with per-vertex normals (x y z) and colours (r g b).
    #[derive(Debug, Default)]
    struct TerrainMesh {
        mesh: MeshArrays,
        normals: Vec<f64>,
        colors: Vec<u8>,
        report: Report,
    }

    unsafe extern "C++" {
        include!("asperity/progress.hpp");
        /// A C++ progress function (`asperity::ProgressFunction`), exceptions caught.
        type ProgressCallback;
        /// Whether a function is set.
        fn watching(self: &ProgressCallback) -> bool;
        /// The function's answer to one report (false: stop).
        fn report(self: &ProgressCallback, stage: &str, done: u64, total: u64) -> bool;
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
        /// the hierarchy, refined back to full resolution; `hierarchy_fields` (a JSON object
        /// of `HierarchyRequest` fields) is laid over the recipe's `[hierarchy]` table.
        fn detail(
            positions: &[f64],
            triangles: &[u32],
            recipe_toml: &str,
            hierarchy_fields: &str,
            no_self_intersections: bool,
        ) -> Result<Outcome>;

        /// The mesh repaired as `--repair` does (degenerate and duplicate faces, non-manifold
        /// vertices and edges, orientation, unreferenced vertices); the report is one line.
        fn repair(positions: &[f64], triangles: &[u32]) -> Result<RepairOutcome>;
        /// A terrain mesh from the JSON object of the terrain request's fields (and `tile`, `tile_size`).
        fn terrain_mesh(fields: &str) -> Result<TerrainMesh>;
        /// `asperity noise`'s field at points (`dimension` 2: the image plane; 3: space).
        /// `fields`: the JSON object of the noise request's fields.
        fn noise(points: &[f64], dimension: usize, fields: &str) -> Result<Vec<f64>>;
        /// Normals, curvatures and feature classes of a mesh (`asperity analyze`).
        /// `fields`: the JSON object of the analysis request's fields.
        fn analyze(positions: &[f64], triangles: &[u32], fields: &str) -> Result<Analysis>;
        /// `asperity info`'s validation report, as JSON.
        fn validate(positions: &[f64], triangles: &[u32]) -> Result<String>;
        /// The two-sided Hausdorff distance between two meshes, a share of the first's
        /// bounding-box diagonal (CGAL).
        fn hausdorff(
            reference_positions: &[f64],
            reference_triangles: &[u32],
            other_positions: &[f64],
            other_triangles: &[u32],
        ) -> Result<f64>;
        /// Polygons (corner counts, then their corners) as triangles, n − 2 per polygon in
        /// polygon order (the readers' ear clipping).
        fn triangulate(positions: &[f64], corner_counts: &[u32], corners: &[u32]) -> Result<Vec<u32>>;

        /// The library's default hierarchy options.
        fn default_hierarchy_options() -> HierarchyOptions;

        /// A built hierarchy, every level recorded.
        type BuiltHierarchy;
        /// Builds the hierarchy of a mesh; `corner_uvs` is empty or u v per face corner (6 per
        /// triangle), which every level then carries (seams simplified along themselves).
        fn build_hierarchy(
            positions: &[f64],
            triangles: &[u32],
            corner_uvs: &[f64],
            options: &HierarchyOptions,
            progress: &ProgressCallback,
        ) -> Result<Box<BuiltHierarchy>>;
        /// Levels, the base domain and the input included.
        fn level_count(self: &BuiltHierarchy) -> usize;
        /// Level `l` (0: base domain).
        fn level(self: &BuiltHierarchy, l: usize) -> Result<LevelArrays>;
        /// The parametrization of every input vertex.
        fn parametrization(self: &BuiltHierarchy) -> Result<Parametrization>;
        /// The build's report (levels, base vertices, seconds).
        fn report(self: &BuiltHierarchy) -> Report;
        /// Build time by stage, as JSON.
        fn stages_json(self: &BuiltHierarchy) -> String;
        fn report_json(self: &BuiltHierarchy) -> Result<String>;
        /// Refines whole up to `base_level`, then only the vertices `inside` marks (one
        /// byte per input vertex) and what they need.
        fn refine_region(
            self: &BuiltHierarchy,
            inside: &[u8],
            base_level: usize,
            progress: &ProgressCallback,
        ) -> Result<RegionOutcome>;

        /// A refinement in progress, level by level from the base domain.
        type Refinement<'a>;
        /// Starts refining `hierarchy`.
        ///
        /// # Safety
        /// C++ must keep `hierarchy` alive and unmoved while the refinement lives (the
        /// C++ wrapper holds both in one call).
        unsafe fn start_refinement<'a>(hierarchy: &'a BuiltHierarchy) -> Result<Box<Refinement<'a>>>;
        /// The current level (0: base domain).
        fn current_level(self: &Refinement) -> usize;
        /// Whether the input's level is reached.
        fn finished(self: &Refinement) -> bool;
        /// The current level's mesh, normals and vertex levels.
        fn view(self: &mut Refinement) -> Result<ViewArrays>;
        /// The current level's curvatures and feature classes (computed once per level).
        fn view_analysis(self: &mut Refinement) -> Result<Analysis>;
        /// Moves the current level's vertices (x y z per vertex, in `view` order); later
        /// levels insert their vertices on the moved surface (thesis §4.5.1).
        fn set_positions(self: &mut Refinement, positions: &[f64]) -> Result<()>;
        /// Refines one level: every vertex when `inside` is empty, else the vertices it marks.
        fn refine_next(self: &mut Refinement, inside: &[u8]) -> Result<()>;
        /// The current mesh.
        fn result(self: &Refinement) -> Result<LevelArrays>;
    }
}

/// Runs `f`, turning errors into `code|message` and panics into internal errors, so that
/// none unwinds into C++.
fn guarded<T>(f: impl FnOnce() -> asperity::Result<T>) -> Result<T, String> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(Ok(value)) => Ok(value),
        Ok(Err(e)) => Err(format!("{}|{e}", e.exit_code())),
        Err(_) => Err("1|asperity: internal error (a bug: please report it)".into()),
    }
}
