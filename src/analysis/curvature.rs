//! Discrete curvatures (thesis §3.1.2; Meyer, Desbrun, Schröder & Barr 2003):
//! mean curvature from the cotangent Laplace–Beltrami operator with mixed Voronoi areas
//! (eq. 3.4–3.5), Gaussian curvature by angle deficit (eq. 3.6), principal curvatures from
//! both (eq. 3.7, with H² − K clamped at 0).
//!
//! Sign convention: H > 0 where the surface bends away from its normal (a sphere with
//! outward normals has H = 1/r). Boundary vertices have no closed 1-ring, so their values
//! are the mean of their interior neighbours' values (0 when they have none); their
//! angle deficit is the boundary form π − Σθ (geodesic curvature), used by Gauss–Bonnet.

use std::f64::consts::{PI, TAU};

use glam::DVec3;
use rayon::prelude::*;

use super::FaceGeometry;
use crate::mesh::{Adjacency, Mesh};

/// Per-vertex curvatures.
#[derive(Debug, Clone, Default)]
pub struct Curvatures {
    /// Signed mean curvature H.
    pub mean: Vec<f64>,
    /// Gaussian curvature K.
    pub gaussian: Vec<f64>,
    /// Larger principal curvature H + √(H² − K).
    pub k1: Vec<f64>,
    /// Smaller principal curvature H − √(H² − K).
    pub k2: Vec<f64>,
    /// Mixed Voronoi area of each vertex.
    pub area: Vec<f64>,
}

/// What one vertex gathers from its faces.
#[derive(Default)]
struct VertexSums {
    laplacian: DVec3,
    mixed_area: f64,
    angle_sum: f64,
}

fn cot(a: DVec3, b: DVec3) -> f64 {
    let s = a.cross(b).length();
    if s > 0.0 { a.dot(b) / s } else { 0.0 }
}

/// Sums of vertex `v` over its faces, in increasing face order (so the result does not
/// depend on how vertices are distributed over threads).
fn gather(mesh: &Mesh, adjacency: &Adjacency, faces: &FaceGeometry, v: usize) -> VertexSums {
    let mut sums = VertexSums::default();
    let xi = mesh.positions[v];
    for &f in adjacency.faces(v) {
        let t = mesh.triangles[f as usize];
        let k = t.iter().position(|&w| w as usize == v).expect("vertex of face");
        let xj = mesh.positions[t[(k + 1) % 3] as usize];
        let xk = mesh.positions[t[(k + 2) % 3] as usize];
        let (eij, eik, ejk) = (xj - xi, xk - xi, xk - xj);
        let area = faces.areas[f as usize];
        if area <= 0.0 {
            continue;
        }
        let cot_j = cot(xi - xj, xk - xj); // angle at j, opposite edge ik
        let cot_k = cot(xi - xk, xj - xk); // angle at k, opposite edge ij
        sums.laplacian += cot_k * eij + cot_j * eik;
        sums.angle_sum += faces.angles[f as usize][k];
        let obtuse_i = eij.dot(eik) < 0.0;
        let obtuse_other = (xi - xj).dot(ejk) < 0.0 || (xi - xk).dot(-ejk) < 0.0;
        sums.mixed_area += if obtuse_i {
            area / 2.0
        } else if obtuse_other {
            area / 4.0
        } else {
            (eij.length_squared() * cot_k + eik.length_squared() * cot_j) / 8.0
        };
    }
    sums
}

/// Per-vertex angle deficit: 2π − Σθ at interior vertices, π − Σθ at boundary vertices.
/// Over a mesh, the deficits sum to 2πχ (discrete Gauss–Bonnet).
pub fn angle_deficits(mesh: &Mesh, adjacency: &Adjacency) -> Vec<f64> {
    let faces = FaceGeometry::of(mesh);
    (0..mesh.positions.len())
        .into_par_iter()
        .map(|v| {
            let full = if adjacency.is_boundary(v) { PI } else { TAU };
            if adjacency.faces(v).is_empty() { 0.0 } else { full - gather(mesh, adjacency, &faces, v).angle_sum }
        })
        .collect()
}

/// Mean, Gaussian and principal curvatures of every vertex; `normals` orient H.
pub fn curvatures(mesh: &Mesh, adjacency: &Adjacency, faces: &FaceGeometry, normals: &[DVec3]) -> Curvatures {
    let n = mesh.positions.len();
    let raw: Vec<(f64, f64, f64)> = (0..n)
        .into_par_iter()
        .map(|v| {
            let s = gather(mesh, adjacency, faces, v);
            if s.mixed_area <= 0.0 {
                return (0.0, 0.0, 0.0);
            }
            // Δx = (1 / 2A) Σ (cot α + cot β)(xⱼ − xᵢ) = −2H n.
            let laplacian = s.laplacian / (2.0 * s.mixed_area);
            let magnitude = 0.5 * laplacian.length();
            let mean = if laplacian.dot(normals[v]) > 0.0 { -magnitude } else { magnitude };
            (mean, (TAU - s.angle_sum) / s.mixed_area, s.mixed_area)
        })
        .collect();
    let interior_mean = |v: usize, pick: fn(&(f64, f64, f64)) -> f64| {
        let inner: Vec<f64> = adjacency
            .neighbours(v)
            .iter()
            .filter(|&&w| !adjacency.is_boundary(w as usize))
            .map(|&w| pick(&raw[w as usize]))
            .collect();
        if inner.is_empty() { 0.0 } else { inner.iter().sum::<f64>() / inner.len() as f64 }
    };
    let (mean, gaussian): (Vec<f64>, Vec<f64>) = (0..n)
        .into_par_iter()
        .map(|v| {
            if adjacency.is_boundary(v) {
                (interior_mean(v, |r| r.0), interior_mean(v, |r| r.1))
            } else {
                (raw[v].0, raw[v].1)
            }
        })
        .unzip();
    let (k1, k2) = mean
        .iter()
        .zip(&gaussian)
        .map(|(&h, &k)| {
            let d = (h * h - k).max(0.0).sqrt();
            (h + d, h - d)
        })
        .unzip();
    Curvatures { mean, gaussian, k1, k2, area: raw.iter().map(|r| r.2).collect() }
}
