//! Garland–Heckbert quadrics (Garland & Heckbert 1997, "Surface simplification using quadric
//! error metrics", §4): pure Rust arithmetic; CGAL computes them per vertex
//! (`ffi::vertex_quadrics`).

use glam::DVec3;

/// A Garland–Heckbert quadric: the upper triangle of a symmetric 4×4 matrix, row-major
/// (q00 q01 q02 q03 q11 q12 q13 q22 q23 q33).
#[derive(Debug, Clone, Copy, PartialEq, Default, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(transparent)]
pub struct Quadric(pub [f64; 10]);

impl Quadric {
    /// The quadric error [p 1] Q [p 1]ᵀ (a sum of squared plane distances).
    pub fn error(&self, p: DVec3) -> f64 {
        let [a, b, c, d, e, f, g, h, i, j] = self.0;
        let (x, y, z) = (p.x, p.y, p.z);
        x * (a * x + 2.0 * (b * y + c * z + d)) + y * (e * y + 2.0 * (f * z + g)) + z * (h * z + 2.0 * i) + j
    }

    /// The total weight of the planes summed into the quadric: the trace of its 3×3 part
    /// (a plane with normal n adds |n|²).
    pub fn weight(&self) -> f64 {
        self.0[0] + self.0[4] + self.0[7]
    }

    /// The weighted mean of the squared plane distances at `p`: [`Quadric::error`] divided
    /// by [`Quadric::weight`] (meshoptimizer's normalisation), so a quadric that has
    /// absorbed many planes is not dearer for that alone. Zero for an empty quadric.
    pub fn mean_error(&self, p: DVec3) -> f64 {
        let w = self.weight();
        if w > 0.0 { (self.error(p) / w).max(0.0) } else { 0.0 }
    }

    /// Adds `scale` times `other`.
    pub fn add_scaled(&mut self, other: &Quadric, scale: f64) {
        for (a, b) in self.0.iter_mut().zip(other.0) {
            *a += scale * b;
        }
    }
}

/// Gives a removed vertex's quadric to the two ends of the diagonal its weld leaves, half
/// to each: they take over the region it stood for (Garland & Heckbert §4 sum the quadrics
/// of a collapse; a cluster's removal has two heirs). A one-piece build does it level by
/// level, and a partitioned build's part along its removals before it hands its quadrics
/// over, so both sum the same shares.
pub fn share_removed_quadric<T>(quadrics: &mut T, removed: u32, diagonal: [u32; 2])
where
    T: std::ops::IndexMut<usize, Output = Quadric> + ?Sized,
{
    let q = quadrics[removed as usize];
    for end in diagonal {
        quadrics[end as usize].add_scaled(&q, 0.5);
    }
}
