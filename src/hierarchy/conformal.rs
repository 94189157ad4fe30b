//! The conformal 1-ring flattening of MAPS (Lee et al. 1998; thesis §3.2.3, eq. 3.12–3.13)
//! and the planar point location that maps parameter points onto a retriangulated ring.

use glam::{DVec2, DVec3};

use super::rings::RingVec;

/// A removed vertex's 1-ring mapped to the plane by z^a: the vertex sits at the origin,
/// ring vertex k at r_k^a·e^{i·a·θ_k}, with θ_k the sum of the 3D angles between
/// consecutive spokes and a = 2π/θ_n (closed ring). Radii are divided by their mean first,
/// so the map does not depend on the model's units (r^a is not scale-invariant for a ≠ 1).
#[derive(Debug, Clone)]
pub struct Flattening {
    /// One planar point per ring vertex, in ring order.
    pub points: RingVec<DVec2>,
}

impl Flattening {
    /// Flattens the ring of the vertex at `centre`: closed around it, or for a vertex on a
    /// `boundary` open, onto the upper half-disk (a = π/θ_n, so the first ring vertex lands
    /// on the positive real axis, the last on the negative one, and the vertex — the
    /// origin — on the segment between). `None` for a degenerate ring.
    pub fn of_star(centre: DVec3, ring: &[DVec3], boundary: bool) -> Option<Self> {
        let closed = !boundary;
        let n = ring.len();
        if n < if closed { 3 } else { 2 } {
            return None;
        }
        let spokes: RingVec<DVec3> = ring.iter().map(|&p| p - centre).collect();
        let radii: RingVec<f64> = spokes.iter().map(|s| s.length()).collect();
        if radii.iter().any(|&r| r <= 0.0 || !r.is_finite()) {
            return None;
        }
        let mut theta = RingVec::with_capacity(n);
        let mut total = 0.0;
        for k in 0..n {
            theta.push(total);
            if closed || k + 1 < n {
                total += spokes[k].angle_between(spokes[(k + 1) % n]);
            }
        }
        if total <= 0.0 || !total.is_finite() {
            return None;
        }
        let a = if closed { std::f64::consts::TAU } else { std::f64::consts::PI } / total;
        let mean = radii.iter().sum::<f64>() / n as f64;
        let points = (0..n)
            .map(|k| {
                let r = (radii[k] / mean).powf(a);
                let t = a * theta[k];
                DVec2::new(r * t.cos(), r * t.sin())
            })
            .collect();
        Some(Flattening { points })
    }
}

/// Twice the signed area of the planar triangle (a, b, c): positive when counter-clockwise.
pub fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Barycentric coordinates of `p` in the planar triangle `t` (any sign).
pub fn barycentric(p: DVec2, t: [DVec2; 3]) -> [f64; 3] {
    let area = orient(t[0], t[1], t[2]);
    let w0 = orient(p, t[1], t[2]) / area;
    let w1 = orient(t[0], p, t[2]) / area;
    [w0, w1, 1.0 - w0 - w1]
}

/// Locates `p` among planar triangles: the triangle whose smallest barycentric coordinate
/// is largest (so `p` inside some triangle is found in it), with the coordinates clamped to
/// be non-negative and renormalised — a point that rounding put just outside every triangle
/// lands on the nearest edge.
pub fn locate(p: DVec2, triangles: &[[DVec2; 3]]) -> (usize, [f64; 3]) {
    let best = locate_from(p, triangles, 0, (0, [1.0, 0.0, 0.0], f64::NEG_INFINITY));
    (best.0, clamp_barycentric(best.1))
}

/// Where [`locate`]'s search stands: a triangle, its unclamped barycentric coordinates and
/// their smallest.
pub type Located = (usize, [f64; 3], f64);

/// [`locate`]'s search over `triangles` (numbered from `first`) continued from `best` (a
/// triangle, its unclamped coordinates and their smallest): the triangle whose smallest
/// barycentric coordinate is largest, the earlier one on ties.
pub fn locate_from(p: DVec2, triangles: &[[DVec2; 3]], first: usize, mut best: Located) -> Located {
    for (i, t) in triangles.iter().enumerate() {
        let w = barycentric(p, *t);
        let worst = w[0].min(w[1]).min(w[2]);
        if worst > best.2 {
            best = (first + i, w, worst);
        }
    }
    best
}

/// Clamps barycentric coordinates to [0, 1] and renormalises them to sum to one.
pub fn clamp_barycentric(w: [f64; 3]) -> [f64; 3] {
    let c = w.map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 });
    let sum = c[0] + c[1] + c[2];
    if sum <= 0.0 {
        return [1.0 / 3.0; 3];
    }
    let w0 = c[0] / sum;
    let w1 = c[1] / sum;
    [w0, w1, (1.0 - w0 - w1).max(0.0)]
}

/// The point with barycentric coordinates `w` in the 3D triangle `t`.
pub fn interpolate(t: [DVec3; 3], w: [f64; 3]) -> DVec3 {
    t[0] * w[0] + t[1] * w[1] + t[2] * w[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_regular_ring_flattens_to_a_regular_polygon() {
        let ring: Vec<DVec3> = (0..6)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 6.0;
                DVec3::new(2.0 * t.cos(), 2.0 * t.sin(), 0.0)
            })
            .collect();
        let f = Flattening::of_star(DVec3::ZERO, &ring, false).unwrap();
        for (k, p) in f.points.iter().enumerate() {
            let t = k as f64 * std::f64::consts::TAU / 6.0;
            assert!((p.x - t.cos()).abs() < 1e-12 && (p.y - t.sin()).abs() < 1e-12, "{k}: {p}");
        }
    }

    #[test]
    fn a_cone_apex_opens_to_a_full_turn() {
        // Apex of a pyramid: the spoke angles sum to less than 2π; z^a stretches them to 2π.
        let ring = [
            DVec3::new(1.0, 0.0, -1.0),
            DVec3::new(0.0, 1.0, -1.0),
            DVec3::new(-1.0, 0.0, -1.0),
            DVec3::new(0.0, -1.0, -1.0),
        ];
        let f = Flattening::of_star(DVec3::ZERO, &ring, false).unwrap();
        for k in 0..4 {
            let a = f.points[k];
            let b = f.points[(k + 1) % 4];
            assert!((a.angle_to(b) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        }
    }

    #[test]
    fn location_clamps_points_just_outside() {
        let t = [DVec2::ZERO, DVec2::X, DVec2::Y];
        let (i, w) = locate(DVec2::new(0.5, -1e-14), &[t]);
        assert_eq!(i, 0);
        assert!(w.iter().all(|&x| x >= 0.0));
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    }
}
