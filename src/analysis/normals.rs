//! Face normals (thesis eq. 3.1) and vertex normals as weighted averages of the incident
//! face normals (eq. 3.2) with uniform, area or angle weights (Botsch et al. 2010, §3.2).

use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::mesh::{Adjacency, Mesh};

/// Weights α(T) of eq. 3.2.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum NormalWeighting {
    /// α = 1.
    Uniform,
    /// α = area of the face.
    Area,
    /// α = angle of the face at the vertex (best behaved; the default).
    #[default]
    Angle,
}

/// Per-face quantities every analysis stage needs, computed once.
#[derive(Debug, Clone)]
pub struct FaceGeometry {
    /// Unit normals (eq. 3.1); zero for degenerate faces.
    pub normals: Vec<DVec3>,
    /// Areas.
    pub areas: Vec<f64>,
    /// Barycentres.
    pub centroids: Vec<DVec3>,
    /// Interior angle at each corner, in the face's vertex order.
    pub angles: Vec<[f64; 3]>,
}

impl FaceGeometry {
    /// The geometry of every face of `mesh`.
    pub fn of(mesh: &Mesh) -> Self {
        let (normals, (areas, (centroids, angles))) = (0..mesh.triangles.len())
            .into_par_iter()
            .map(|f| {
                let [a, b, c] = mesh.triangle_points(f);
                let cross = (b - a).cross(c - a);
                let angle = |p: DVec3, q: DVec3, r: DVec3| {
                    let theta = (q - p).angle_between(r - p);
                    if theta.is_finite() { theta } else { 0.0 }
                };
                (
                    cross.normalize_or_zero(),
                    (0.5 * cross.length(), ((a + b + c) / 3.0, [angle(a, b, c), angle(b, c, a), angle(c, a, b)])),
                )
            })
            .collect();
        FaceGeometry { normals, areas, centroids, angles }
    }

    /// The angle of face `f` at its corner `v`.
    pub fn angle_at(&self, mesh: &Mesh, f: usize, v: u32) -> f64 {
        let k = mesh.triangles[f].iter().position(|&w| w == v).expect("vertex of the face");
        self.angles[f][k]
    }
}

/// Unit normal of every face, (xⱼ − xᵢ) × (xₖ − xᵢ) normalised (eq. 3.1); zero for a
/// degenerate face.
pub fn face_normals(mesh: &Mesh) -> Vec<DVec3> {
    (0..mesh.triangles.len())
        .into_par_iter()
        .map(|f| {
            let [a, b, c] = mesh.triangle_points(f);
            (b - a).cross(c - a).normalize_or_zero()
        })
        .collect()
}

/// Unit vertex normals (eq. 3.2); zero for a vertex without non-degenerate faces.
pub fn vertex_normals(
    mesh: &Mesh,
    adjacency: &Adjacency,
    faces: &FaceGeometry,
    weighting: NormalWeighting,
) -> Vec<DVec3> {
    (0..mesh.positions.len())
        .into_par_iter()
        .map(|v| {
            let mut sum = DVec3::ZERO;
            for &f in adjacency.faces(v) {
                let f = f as usize;
                let weight = match weighting {
                    NormalWeighting::Uniform => 1.0,
                    NormalWeighting::Area => faces.areas[f],
                    NormalWeighting::Angle => faces.angle_at(mesh, f, v as u32),
                };
                sum += weight * faces.normals[f];
            }
            sum.normalize_or_zero()
        })
        .collect()
}
