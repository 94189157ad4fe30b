//! Side-by-side comparison of our four-face-cluster simplification with the reference
//! decimators at the same vertex budget: OpenMesh (`DecimaterT` + `ModQuadricT`), CGAL
//! (`edge_collapse` with Garland–Heckbert plane policies) and meshoptimizer (`simplify`).
//! Quality is measured by CGAL: symmetric Hausdorff distance and the RMS of the vertex-to-
//! surface distances both ways, as fractions of the input's bounding-box diagonal.

use std::time::Instant;

use glam::DVec3;
use serde::Serialize;

use super::{LevelMesh, SimplifyOptions, TargetReport, build};
use crate::analysis::{FaceGeometry, classify, voting_tensors};
use crate::error::Result;
use crate::ffi::{self, HausdorffOptions};
use crate::mesh::{Adjacency, Mesh, UnitFrame};

/// One decimator's result.
#[derive(Debug, Clone, Serialize)]
pub struct CompareRow {
    /// "asperity", "openmesh", "cgal" or "meshoptimizer".
    pub method: String,
    /// Vertices of the result.
    pub vertices: usize,
    /// Faces of the result.
    pub faces: usize,
    /// Time spent simplifying (quality measures excluded).
    pub seconds: f64,
    /// Symmetric Hausdorff distance / bounding-box diagonal.
    pub hausdorff: f64,
    /// RMS of vertex-to-surface distances both ways / bounding-box diagonal.
    pub rms: f64,
    /// Smallest triangle angle, degrees.
    pub min_angle_deg: f64,
    /// Input feature vertices (corners, strong edges) still present at their position.
    pub features_kept: usize,
    /// Share of the triangles with an angle under 5° (slivers).
    pub sliver_share: f64,
    /// Pairs of the result's faces that intersect beyond a shared vertex or edge (CGAL's
    /// exact predicates): a surface that cuts itself. Compare with
    /// [`CompareReport::input_self_intersections`], the input's own.
    pub self_intersections: usize,
    /// The 1st percentile of the triangles' smallest angles, degrees.
    pub min_angle_p1_deg: f64,
    /// The vertex count the method was asked for: the requested budget, or the count
    /// another method stopped at above it (then this row was run again to match).
    pub target_vertices: usize,
    /// Ours: what gave way to reach the target ("nothing" when nothing did); `None` for
    /// the reference methods.
    pub gave_way: Option<String>,
    /// Ours, when it stopped short of the target: what stopped it.
    pub stopped_by: Option<String>,
}

/// The reference decimators run by [`compare`].
pub const METHODS: [&str; 4] = ["asperity", "openmesh", "cgal", "meshoptimizer"];

/// Rows within this share of each other's vertex counts compare like with like.
pub const SAME_COUNT: f64 = 0.005;

/// Whether two vertex counts are the same for a comparison (within [`SAME_COUNT`]).
pub fn same_count(a: usize, b: usize) -> bool {
    a.abs_diff(b) as f64 <= SAME_COUNT * a.max(b) as f64
}

/// Both tables of a comparison (#34): every method at the requested target, so a method
/// that stops short shows it there, and, where the counts differ by more than
/// [`SAME_COUNT`], every method again at the smallest count all reached (like with like).
#[derive(Debug, Clone, Serialize)]
pub struct CompareReport {
    /// The vertex count asked for.
    pub target_vertices: usize,
    /// Pairs of the input's faces that intersect beyond a shared vertex or edge (an
    /// assembly's touching parts): a result's [`CompareRow::self_intersections`] beyond
    /// these are cuts the method made.
    pub input_self_intersections: usize,
    /// Each method asked for the target.
    pub at_target: Vec<CompareRow>,
    /// Each method at the smallest count every method reached, when the counts at the
    /// target differ.
    pub at_common_count: Option<CommonCount>,
}

/// The like-with-like table of a [`CompareReport`].
#[derive(Debug, Clone, Serialize)]
pub struct CommonCount {
    /// The smallest vertex count every method reached at the target.
    pub vertices: usize,
    /// Each method at that count (rows already there are those of the target's table).
    pub rows: Vec<CompareRow>,
}

impl CompareReport {
    /// The rows that compare like with like: the common count's table when there is
    /// one, else the target's.
    pub fn like_with_like(&self) -> &[CompareRow] {
        self.at_common_count.as_ref().map_or(&self.at_target, |c| &c.rows)
    }
}

/// The like-with-like rows of [`compare_report`] (see [`CompareReport::like_with_like`]).
///
/// # Errors
/// As [`compare_report`].
pub fn compare(
    mesh: &Mesh,
    target_vertices: usize,
    methods: &[&str],
    ours: &SimplifyOptions,
) -> Result<Vec<CompareRow>> {
    Ok(compare_report(mesh, target_vertices, methods, ours)?.like_with_like().to_vec())
}

/// Runs `methods` (names from [`METHODS`]) on `mesh` down to `target_vertices`, ours with
/// the options `ours` (its target replaced), then, when their counts differ by more than
/// [`SAME_COUNT`], runs each method not already there again to the largest count among
/// them (the smallest count all reached).
///
/// # Errors
/// Whatever a decimator or a measure reports for this mesh.
pub fn compare_report(
    mesh: &Mesh,
    target_vertices: usize,
    methods: &[&str],
    ours: &SimplifyOptions,
) -> Result<CompareReport> {
    let reference = Reference::of(mesh)?;
    let run = |method: &str, target: usize| -> Result<CompareRow> {
        let start = Instant::now();
        let (result, report) = decimate(mesh, method, target, ours)?;
        let mut row = reference.row(method, target, &result, start.elapsed().as_secs_f64())?;
        if let Some(report) = report {
            row.gave_way = Some(report.gave_way());
            row.stopped_by = report.stopped_by;
        }
        Ok(row)
    };
    let mut at_target = Vec::with_capacity(methods.len());
    crate::progress::report("compare", 0, methods.len() as u64);
    for &method in methods {
        at_target.push(run(method, target_vertices)?);
        crate::progress::report("compare", at_target.len() as u64, methods.len() as u64);
    }
    let top = at_target.iter().map(|r| r.vertices).max().unwrap_or(0);
    let at_common_count = if at_target.iter().all(|r| same_count(r.vertices, top)) {
        None
    } else {
        let rows = at_target
            .iter()
            .map(|row| if same_count(row.vertices, top) { Ok(row.clone()) } else { run(&row.method, top) })
            .collect::<Result<Vec<_>>>()?;
        Some(CommonCount { vertices: top, rows })
    };
    let input_self_intersections = reference.self_intersections;
    Ok(CompareReport { target_vertices, input_self_intersections, at_target, at_common_count })
}

/// One method's simplification of `mesh` to `target` vertices, with ours' target report.
fn decimate(mesh: &Mesh, method: &str, target: usize, ours: &SimplifyOptions) -> Result<(Mesh, Option<TargetReport>)> {
    Ok(match method {
        "asperity" => {
            let options = SimplifyOptions { target_vertices: Some(target), record_levels: false, ..ours.clone() };
            let hierarchy = build(mesh, &options)?;
            (hierarchy.base_mesh().mesh, Some(hierarchy.target))
        }
        "openmesh" => (ffi::openmesh_decimate(mesh, target)?, None),
        "cgal" => (ffi::cgal_decimate(mesh, target)?, None),
        "meshoptimizer" => (meshopt_to_vertices(mesh, target), None),
        other => {
            return Err(crate::Error::InvalidInput(format!(
                "unknown method '{other}' (expected one of {})",
                METHODS.join(", ")
            )));
        }
    })
}

/// Symmetric Hausdorff distance (CGAL) as a fraction of `reference`'s bounding-box diagonal.
/// Both are measured in `reference`'s unit frame, so the result does not depend on the
/// model's units and stays finite for coordinates near the ends of the f64 range.
///
/// # Errors
/// [`crate::Error::InvalidInput`] for a reference whose extent overflows; CGAL's errors.
pub fn relative_hausdorff(reference: &Mesh, other: &Mesh) -> Result<f64> {
    let unit = UnitFrame::of(reference)?;
    ffi::hausdorff_distance(&unit.apply(reference), &unit.apply(other), HausdorffOptions::default())
}

/// The input of a comparison, prepared once for measuring every result: its unit frame,
/// its copy in that frame, its feature vertices' positions and how often it cuts itself.
struct Reference {
    unit: UnitFrame,
    input_unit: Mesh,
    features: Vec<DVec3>,
    self_intersections: usize,
}

/// Pairs of `mesh`'s faces that intersect beyond a shared vertex or edge.
fn self_intersection_count(mesh: &Mesh) -> Result<usize> {
    Ok(super::added_triangle_intersections(&mesh.positions, &[], &mesh.triangles)?.len())
}

impl Reference {
    fn of(input: &Mesh) -> Result<Self> {
        let adjacency = Adjacency::of(input);
        let geometry = FaceGeometry::of(input);
        let classes =
            classify(&input.positions, &adjacency, &voting_tensors(input, &adjacency, &geometry), &Default::default());
        let features =
            classes.iter().enumerate().filter(|(_, c)| c.is_sharp()).map(|(v, _)| input.positions[v]).collect();
        let unit = UnitFrame::of(input)?;
        let self_intersections = self_intersection_count(input)?;
        Ok(Reference { unit, input_unit: unit.apply(input), features, self_intersections })
    }

    /// `method`'s row for `result`, asked for `target` vertices, made in `seconds`.
    /// Distances are measured in the input's unit frame: they come out as fractions of its
    /// diagonal and stay finite whatever the model's units.
    fn row(&self, method: &str, target: usize, result: &Mesh, seconds: f64) -> Result<CompareRow> {
        if result.face_count() == 0 {
            // A method that dropped every face (meshoptimizer can, on a small assembly)
            // has no distance to measure: it is infinitely far, and says so.
            return Ok(CompareRow {
                method: method.to_string(),
                vertices: result.vertex_count(),
                faces: 0,
                seconds,
                hausdorff: f64::INFINITY,
                rms: f64::INFINITY,
                min_angle_deg: 0.0,
                features_kept: 0,
                sliver_share: 0.0,
                self_intersections: 0,
                min_angle_p1_deg: 0.0,
                target_vertices: target,
                gave_way: None,
                stopped_by: Some("the result has no faces left".to_string()),
            });
        }
        let result_unit = self.unit.apply(result);
        let hausdorff = ffi::hausdorff_distance(&self.input_unit, &result_unit, HausdorffOptions::default())?;
        let there = ffi::point_distances(&self.input_unit.positions, &result_unit)?;
        let back = ffi::point_distances(&result_unit.positions, &self.input_unit)?;
        let squares: f64 = there.iter().chain(&back).map(|d| d * d).sum();
        let rms = (squares / (there.len() + back.len()).max(1) as f64).sqrt();
        let mut present: Vec<[u64; 3]> = result.positions.iter().map(|p| p.to_array().map(f64::to_bits)).collect();
        present.sort_unstable();
        let features_kept =
            self.features.iter().filter(|p| present.binary_search(&p.to_array().map(f64::to_bits)).is_ok()).count();
        let shape = ShapeReport::of(result);
        Ok(CompareRow {
            method: method.to_string(),
            vertices: result.vertex_count(),
            faces: result.face_count(),
            seconds,
            hausdorff,
            rms,
            min_angle_deg: shape.min_angle_deg,
            features_kept,
            sliver_share: shape.sliver_share,
            self_intersections: self_intersection_count(result)?,
            min_angle_p1_deg: shape.min_angle_p1_deg,
            target_vertices: target,
            gave_way: None,
            stopped_by: None,
        })
    }
}

/// The triangle shapes of a mesh: its smallest angle, the 1st percentile of the triangles'
/// smallest angles and the share of slivers (a smallest angle under 5°).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ShapeReport {
    /// Smallest angle, degrees (180 for a mesh without faces).
    pub min_angle_deg: f64,
    /// 1st percentile of the triangles' smallest angles, degrees.
    pub min_angle_p1_deg: f64,
    /// Share of triangles with an angle under 5°.
    pub sliver_share: f64,
}

impl ShapeReport {
    /// Measures `mesh`'s triangles.
    pub fn of(mesh: &Mesh) -> Self {
        let mut angles: Vec<f64> = (0..mesh.face_count())
            .map(|f| {
                let [a, b, c] = mesh.triangle_points(f);
                super::cost::min_angle(a, b, c).to_degrees()
            })
            .collect();
        if angles.is_empty() {
            return ShapeReport { min_angle_deg: 180.0, min_angle_p1_deg: 180.0, sliver_share: 0.0 };
        }
        angles.sort_by(f64::total_cmp);
        let slivers = angles.partition_point(|&a| a < 5.0);
        ShapeReport {
            min_angle_deg: angles[0],
            min_angle_p1_deg: angles[(angles.len() - 1) / 100],
            sliver_share: slivers as f64 / angles.len() as f64,
        }
    }
}

/// meshoptimizer's `simplify` (attribute-free, error bound lifted) to `target_vertices`:
/// its budget is an index count, so the count for a surface of the input's topology with
/// that many vertices is tried first, then corrected from the vertices it gave (a few
/// secant steps, F ≈ 2V) until the count is within [`SAME_COUNT`]; the closest result is
/// kept. Vertices keep their positions.
fn meshopt_to_vertices(mesh: &Mesh, target_vertices: usize) -> Mesh {
    let report = crate::mesh::ValidationReport::of(mesh);
    let boundary_edges = 2 * report.edges as i64 - 3 * report.faces as i64;
    let mut faces = (2 * target_vertices as i64 - 2 * report.euler + boundary_edges).max(1);
    let mut best: Option<Mesh> = None;
    for _ in 0..8 {
        let result = meshopt_simplify(mesh, faces as usize);
        let got = result.vertex_count();
        let closer =
            best.as_ref().is_none_or(|b| got.abs_diff(target_vertices) < b.vertex_count().abs_diff(target_vertices));
        let done = same_count(got, target_vertices);
        let step = 2 * (target_vertices as i64 - got as i64);
        if closer {
            best = Some(result);
        }
        if done || step == 0 {
            break;
        }
        faces = (faces + step).clamp(1, 3 * mesh.face_count() as i64);
    }
    best.unwrap_or_default()
}

/// meshoptimizer's `simplify` to `faces` triangles.
fn meshopt_simplify(mesh: &Mesh, faces: usize) -> Mesh {
    let points: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.as_vec3().to_array()).collect();
    let adapter =
        meshopt::VertexDataAdapter::new(bytemuck::cast_slice(&points), 12, 0).expect("tightly packed f32 positions");
    let indices = meshopt::simplify(
        mesh.triangles.as_flattened(),
        &adapter,
        faces * 3,
        1.0,
        meshopt::SimplifyOptions::None,
        None,
    );
    let triangles: Vec<[u32; 3]> = indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    LevelMesh::compact(&mesh.positions, &triangles).mesh
}
