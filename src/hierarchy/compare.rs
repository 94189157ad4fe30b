//! Side-by-side comparison of our four-face-cluster simplification with the reference
//! decimators at the same vertex budget: OpenMesh (`DecimaterT` + `ModQuadricT`), CGAL
//! (`edge_collapse` with Garland–Heckbert plane policies) and meshoptimizer (`simplify`).
//! Quality is measured by CGAL: symmetric Hausdorff distance and the RMS of the vertex-to-
//! surface distances both ways, as fractions of the input's bounding-box diagonal.

use std::time::Instant;

use glam::DVec3;
use serde::Serialize;

use super::{KeepFeatures, LevelMesh, SimplifyOptions, build};
use crate::analysis::{FaceGeometry, classify, voting_tensors};
use crate::error::Result;
use crate::ffi::{self, HausdorffOptions};
use crate::mesh::{Adjacency, Mesh};

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
}

/// The reference decimators run by [`compare`].
pub const METHODS: [&str; 4] = ["asperity", "openmesh", "cgal", "meshoptimizer"];

/// Runs `methods` (names from [`METHODS`]) on `mesh` down to `target_vertices`; ours keeps
/// the `keep` feature classes (which can stop it above the budget).
///
/// # Errors
/// Whatever a decimator or a measure reports for this mesh.
pub fn compare(mesh: &Mesh, target_vertices: usize, methods: &[&str], keep: KeepFeatures) -> Result<Vec<CompareRow>> {
    let diagonal = mesh.bounding_box().map_or(1.0, |(lo, hi)| (hi - lo).length()).max(f64::MIN_POSITIVE);
    let adjacency = Adjacency::of(mesh);
    let classes = classify(&adjacency, &voting_tensors(mesh, &adjacency, &FaceGeometry::of(mesh)), &Default::default());
    let features: Vec<DVec3> =
        classes.iter().enumerate().filter(|(_, c)| c.is_sharp()).map(|(v, _)| mesh.positions[v]).collect();
    let mut rows = Vec::new();
    for &method in methods {
        let start = Instant::now();
        let result = match method {
            "asperity" => {
                let options = SimplifyOptions {
                    target_vertices: Some(target_vertices),
                    keep_features: keep,
                    ..SimplifyOptions::default()
                };
                build(mesh, &options)?.base_mesh().mesh
            }
            "openmesh" => ffi::openmesh_decimate(mesh, target_vertices)?,
            "cgal" => ffi::cgal_decimate(mesh, target_vertices)?,
            "meshoptimizer" => meshopt_simplify(mesh, target_vertices),
            other => {
                return Err(crate::Error::InvalidInput(format!(
                    "unknown method '{other}' (expected one of {})",
                    METHODS.join(", ")
                )));
            }
        };
        let seconds = start.elapsed().as_secs_f64();
        rows.push(measure(method, mesh, &result, seconds, diagonal, &features)?);
    }
    Ok(rows)
}

fn measure(
    method: &str,
    input: &Mesh,
    result: &Mesh,
    seconds: f64,
    diagonal: f64,
    features: &[DVec3],
) -> Result<CompareRow> {
    let hausdorff = ffi::hausdorff_distance(input, result, HausdorffOptions::default())? / diagonal;
    let there = ffi::point_distances(&input.positions, result)?;
    let back = ffi::point_distances(&result.positions, input)?;
    let squares: f64 = there.iter().chain(&back).map(|d| d * d).sum();
    let rms = (squares / (there.len() + back.len()).max(1) as f64).sqrt() / diagonal;
    let mut present: Vec<[u64; 3]> = result.positions.iter().map(|p| p.to_array().map(f64::to_bits)).collect();
    present.sort_unstable();
    let features_kept =
        features.iter().filter(|p| present.binary_search(&p.to_array().map(f64::to_bits)).is_ok()).count();
    Ok(CompareRow {
        method: method.to_string(),
        vertices: result.vertex_count(),
        faces: result.face_count(),
        seconds,
        hausdorff,
        rms,
        min_angle_deg: min_angle_degrees(result),
        features_kept,
    })
}

fn min_angle_degrees(mesh: &Mesh) -> f64 {
    let mut smallest = std::f64::consts::PI;
    for f in 0..mesh.face_count() {
        let [a, b, c] = mesh.triangle_points(f);
        for (p, q, r) in [(a, b, c), (b, c, a), (c, a, b)] {
            smallest = smallest.min((q - p).angle_between(r - p));
        }
    }
    smallest.to_degrees()
}

/// meshoptimizer's `simplify` (attribute-free, error bound lifted) to the index count of a
/// `target_vertices`-vertex surface of the input's topology; vertices keep their positions.
fn meshopt_simplify(mesh: &Mesh, target_vertices: usize) -> Mesh {
    let report = crate::mesh::ValidationReport::of(mesh);
    let chi = report.euler;
    let boundary_edges = 2 * report.edges as i64 - 3 * report.faces as i64;
    let faces = (2 * target_vertices as i64 - 2 * chi + boundary_edges).max(1) as usize;
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
