//! Shading: corner normals with a crease angle, base colours from the chosen source, and
//! two-sided lighting with a key light, a fill light and a little specular, in the camera
//! frame.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::camera::Camera;
use crate::mesh::Mesh;

/// The colour of surfaces without colour information: a light clay.
pub const CLAY: Vec3 = Vec3::new(0.80, 0.76, 0.70);

/// A perceptual ramp (viridis stops) for heights and scalar properties.
const RAMP: [Vec3; 5] = [
    Vec3::new(0.267, 0.005, 0.329),
    Vec3::new(0.229, 0.322, 0.546),
    Vec3::new(0.128, 0.567, 0.551),
    Vec3::new(0.369, 0.789, 0.383),
    Vec3::new(0.993, 0.906, 0.144),
];

/// The ramp colour at `t` in 0..=1 (clamped).
pub fn ramp(t: f64) -> Vec3 {
    let t = (t.clamp(0.0, 1.0) * (RAMP.len() - 1) as f64) as f32;
    let i = (t as usize).min(RAMP.len() - 2);
    RAMP[i].lerp(RAMP[i + 1], t - i as f32)
}

/// Colours by value, mapped through the ramp over the 2nd–98th percentile of the values
/// (so that a few extreme curvatures do not wash the picture out).
pub fn ramp_colors(values: &[f64]) -> Vec<Vec3> {
    let mut sorted: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    let pick = |q: f64| sorted.get(((sorted.len().saturating_sub(1)) as f64 * q).round() as usize).copied();
    let (lo, hi) = (pick(0.02).unwrap_or(0.0), pick(0.98).unwrap_or(1.0));
    let span = (hi - lo).max(1e-300);
    values.iter().map(|v| if v.is_finite() { ramp((v - lo) / span) } else { CLAY }).collect()
}

/// Unnormalised (area-weighted) face normals.
pub fn face_normals(mesh: &Mesh) -> Vec<DVec3> {
    mesh.triangles
        .par_iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
            (b - a).cross(c - a)
        })
        .collect()
}

/// One unit normal per triangle corner: the area-weighted mean of the faces around the
/// corner's vertex whose normals are within `crease_deg` of this face's, so that sharp
/// edges stay sharp and smooth regions are smooth. Per-vertex normals of the mesh, when
/// present, are used as they are.
pub fn corner_normals(mesh: &Mesh, faces: &[DVec3], crease_deg: f64) -> Vec<[Vec3; 3]> {
    if let Some(normals) = &mesh.normals {
        return mesh
            .triangles
            .par_iter()
            .map(|t| t.map(|v| normals[v as usize].normalize_or_zero().as_vec3()))
            .collect();
    }
    let adjacency = crate::mesh::Adjacency::of(mesh);
    let unit: Vec<DVec3> = faces.par_iter().map(|n| n.normalize_or_zero()).collect();
    let cos_crease = crease_deg.to_radians().cos();
    mesh.triangles
        .par_iter()
        .enumerate()
        .map(|(f, t)| {
            t.map(|v| {
                let sum: DVec3 = adjacency
                    .faces(v as usize)
                    .iter()
                    .filter(|&&g| unit[g as usize].dot(unit[f]) >= cos_crease)
                    .map(|&g| faces[g as usize])
                    .sum();
                sum.try_normalize().unwrap_or(unit[f]).as_vec3()
            })
        })
        .collect()
}

/// The lights, in the camera frame (x right, y up, z towards the eye).
pub struct Lighting {
    key: Vec3,
    fill: Vec3,
    half: Vec3,
}

impl Default for Lighting {
    fn default() -> Self {
        let key = Vec3::new(-0.45, 0.6, 0.66).normalize();
        Lighting { key, fill: Vec3::new(0.7, 0.1, 0.7).normalize(), half: (key + Vec3::Z).normalize() }
    }
}

impl Lighting {
    /// The lit colour of `base` with unit normal `n` (camera frame, facing the eye).
    pub fn shade(&self, base: Vec3, n: Vec3) -> Vec3 {
        let diffuse = 0.24 + 0.68 * n.dot(self.key).max(0.0) + 0.22 * n.dot(self.fill).max(0.0);
        let specular = 0.10 * n.dot(self.half).max(0.0).powi(32);
        (base * diffuse + Vec3::splat(specular)).min(Vec3::ONE)
    }

    /// A normal in world space turned to face the eye at `p`, in the camera frame.
    pub fn facing(camera: &Camera, p: DVec3, n: Vec3) -> Vec3 {
        let view = camera.to_view(n.as_dvec3());
        if view.dot(-camera.view_ray(p)) < 0.0 { -view } else { view }
    }
}
