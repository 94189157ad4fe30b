//! Water in a picture (seed 002, "Water"): a plane at sea level over the mesh's extent,
//! coloured per sample by the Fresnel effect — Schlick's approximation
//! F = F₀ + (1 − F₀)(1 − cos θ)⁵ with F₀ = 0.02 for water — between the sky's reflection
//! and what lies below, which fades into the water's colour with the distance the view ray
//! travels under water (so shallow water shows the ground, as at the seed's shores).

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::camera::{Camera, UpAxis};
use super::raster::Frame;

/// Reflectance of water seen straight down.
const F0: f64 = 0.02;
/// The reflected sky.
const SKY: Vec3 = Vec3::new(0.66, 0.80, 0.93);
/// Deep water.
const DEEP: Vec3 = Vec3::new(0.04, 0.18, 0.32);

/// Schlick's Fresnel reflectance for a ray meeting the surface at `cos_theta`.
pub fn fresnel(cos_theta: f64) -> f64 {
    F0 + (1.0 - F0) * (1.0 - cos_theta.clamp(0.0, 1.0)).powi(5)
}

/// Draws the plane `up·p = level` (unit frame) over `bbox`'s horizontal extent into
/// `frame`: wherever the plane is nearer than the drawn surface (or nothing is drawn), the
/// sample becomes F·sky + (1 − F)·(below·e^(−d/clarity) + deep·(1 − e^(−d/clarity))),
/// d the distance under water to the surface behind.
pub(super) fn blend(frame: &mut Frame, camera: &Camera, bbox: (DVec3, DVec3), up: UpAxis, level: f64, clarity: f64) {
    let axis = up.vector();
    let (lo, hi) = bbox;
    let width = frame.width;
    let rows = frame.color.par_chunks_mut(width).zip(frame.depth.par_chunks_mut(width)).zip(frame.covered.par_chunks_mut(width));
    rows.enumerate().for_each(|(y, ((color, depth), covered))| {
        for x in 0..width {
            let (eye, direction) = camera.ray(x as f64 + 0.5, y as f64 + 0.5);
            let along = direction.dot(axis);
            if along.abs() < 1e-12 {
                continue;
            }
            let t = (level - eye.dot(axis)) / along;
            let hit = eye + direction * t;
            let horizontal = (hit - axis * hit.dot(axis), lo - axis * lo.dot(axis), hi - axis * hi.dot(axis));
            let inside = horizontal.0.cmpge(horizontal.1 - 1e-9).all() && horizontal.0.cmple(horizontal.2 + 1e-9).all();
            if t <= 0.0 || !inside {
                continue;
            }
            let surface = covered[x].then(|| 1.0 / f64::from(depth[x]));
            if surface.is_some_and(|z| z < t) {
                continue;
            }
            let below = surface.map_or(f64::INFINITY, |z| (z - t) * direction.length());
            let seen = (-below / clarity).exp() as f32;
            let under = if covered[x] { color[x] * seen + DEEP * (1.0 - seen) } else { DEEP };
            let reflect = fresnel(along.abs() / direction.length()) as f32;
            color[x] = SKY * reflect + under * (1.0 - reflect);
            depth[x] = (1.0 / t) as f32;
            covered[x] = true;
        }
    });
}

#[cfg(test)]
mod tests {
    use super::fresnel;

    #[test]
    fn water_reflects_more_at_grazing_angles() {
        assert!((fresnel(1.0) - 0.02).abs() < 1e-12);
        assert!((fresnel(0.0) - 1.0).abs() < 1e-12);
        assert!(fresnel(0.2) > fresnel(0.5) && fresnel(0.5) > fresnel(0.9));
    }
}
