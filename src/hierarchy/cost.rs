//! What a four-face cluster costs (thesis eq. 4.1, measured as the error the cluster
//! really introduces) and the shape of what it makes.
//!
//! - Where a removed spoke is crossed by the edge that replaces it, the new surface point is
//!   measured against the faces beside the spoke ([`crossing_error`]).
//! - Every vertex already parametrized onto the star (MAPS, Lee et al. 1998), and the
//!   removed vertex itself, is measured against the new triangle its parameter point lands
//!   on ([`point_triangle_distance_squared`]): the successive-mapping bound of Cohen,
//!   Manocha & Olano 1997 (“Simplifying polygonal models using successive mappings”), with
//!   the distance to the triangle rather than to the mapped point, so sliding along a flat
//!   region costs nothing.
//! - Among near-equal costs the larger smallest angle wins ([`choose`]).

use glam::{DVec2, DVec3};

/// One candidate flip or diagonal: its index, its error and the sine of the smallest angle
/// it makes.
#[derive(Debug, Clone, Copy)]
pub(super) struct Choice {
    pub index: usize,
    pub cost: f64,
    pub shape: f64,
}

/// The cheapest choice, except that among choices costing at most 10 % (or `tolerance`)
/// more than it, the one making the widest smallest angle wins (ties: the first).
pub(super) fn choose(choices: &[Choice], tolerance: f64) -> Option<Choice> {
    let cheapest = choices.iter().map(|c| c.cost).fold(f64::INFINITY, f64::min);
    let limit = cheapest * 1.1 + tolerance;
    choices.iter().filter(|c| c.cost <= limit).fold(None, |best: Option<Choice>, &c| match best {
        Some(b) if b.shape >= c.shape => Some(b),
        _ => Some(c),
    })
}

/// Where the spoke from the origin to `a` crosses the segment p–n in the flattening: the
/// parameter along the spoke and along the segment, if they cross.
pub(super) fn spoke_crossing(a: DVec2, p: DVec2, n: DVec2) -> Option<(f64, f64)> {
    let d = n - p;
    let den = a.perp_dot(d);
    if den.abs() <= f64::MIN_POSITIVE {
        return None;
    }
    let t = p.perp_dot(d) / den;
    let s = p.perp_dot(a) / den;
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&s)).then_some((t, s))
}

/// The error of a removed spoke v–`apex`, whose wings are `prev` and `next` (faces
/// (v, prev, apex) and (v, apex, next)), crossed at `x` by the edge that replaces it: the
/// distance from `x` to those two faces. That is where the old and the new surface part
/// most, and it is zero wherever they lie in one plane (a flip within one side of a crease
/// costs nothing, a flip across it costs its bend).
pub(super) fn crossing_error(v: DVec3, prev: DVec3, apex: DVec3, next: DVec3, x: DVec3) -> f64 {
    point_triangle_distance_squared(x, v, prev, apex).min(point_triangle_distance_squared(x, v, apex, next))
}

/// The smallest corner angle of the triangle (a, b, c), radians (0 for a degenerate one).
pub fn min_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (ab, bc, ca) = unit_edges(a, b, c);
    if ab.length_squared() == 0.0 || bc.length_squared() == 0.0 || ca.length_squared() == 0.0 {
        return 0.0;
    }
    let at_a = ab.angle_between(-ca);
    let at_b = bc.angle_between(-ab);
    at_a.min(at_b).min(std::f64::consts::PI - at_a - at_b).max(0.0)
}

/// The sine of the smallest corner angle of the triangle (a, b, c) (0 for a degenerate
/// one): twice its area over the two longer edges, which meet at that corner. The smallest
/// angle is at most 60°, so the sine orders shapes as the angle does, without an arccosine.
pub fn min_angle_sine(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (ab, bc, ca) = unit_edges(a, b, c);
    let lengths = [ab.length_squared(), bc.length_squared(), ca.length_squared()];
    let shortest = lengths.iter().copied().fold(f64::INFINITY, f64::min);
    let product = lengths.iter().product::<f64>() / shortest;
    if product.is_nan() || product <= 0.0 || !product.is_finite() {
        return 0.0;
    }
    (ab.cross(-ca).length() / product.sqrt()).min(1.0)
}

/// The edges a→b, b→c, c→a divided by their largest coordinate, so that products of them
/// neither overflow nor underflow whatever the model's units (zero edges for a point).
fn unit_edges(a: DVec3, b: DVec3, c: DVec3) -> (DVec3, DVec3, DVec3) {
    let (ab, bc, ca) = (b - a, c - b, a - c);
    let scale = ab.abs().max_element().max(bc.abs().max_element()).max(ca.abs().max_element());
    if scale > 0.0 && scale.is_finite() { (ab / scale, bc / scale, ca / scale) } else { (ab, bc, ca) }
}

/// Squared distance from `p` to the triangle (a, b, c): the closest point by Voronoi
/// regions of the vertices, edges and face (Ericson, Real-Time Collision Detection, §5.1.5).
pub fn point_triangle_distance_squared(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length_squared();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length_squared();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v - p).length_squared();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length_squared();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w - p).length_squared();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w - p).length_squared();
    }
    let denom = va + vb + vc;
    if denom.abs() <= f64::MIN_POSITIVE || !denom.is_finite() {
        // A degenerate triangle: the nearest of its edges.
        return [(a, b), (b, c), (c, a)]
            .map(|(s, e)| point_segment_distance_squared(p, s, e))
            .into_iter()
            .fold(f64::INFINITY, f64::min);
    }
    let (v, w) = (vb / denom, vc / denom);
    (a + ab * v + ac * w - p).length_squared()
}

/// Squared distance from `p` to the segment a–b.
pub fn point_segment_distance_squared(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 { ((p - a).dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (a + ab * t - p).length_squared()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_triangle_distance_in_each_region() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        let d = |p: DVec3| point_triangle_distance_squared(p, a, b, c);
        assert!((d(DVec3::new(0.25, 0.25, 2.0)) - 4.0).abs() < 1e-12, "face");
        assert!((d(DVec3::new(-1.0, -1.0, 0.0)) - 2.0).abs() < 1e-12, "vertex a");
        assert!((d(DVec3::new(2.0, 0.0, 1.0)) - 2.0).abs() < 1e-12, "vertex b");
        assert!((d(DVec3::new(0.0, 3.0, 0.0)) - 4.0).abs() < 1e-12, "vertex c");
        assert!((d(DVec3::new(0.5, -1.0, 0.0)) - 1.0).abs() < 1e-12, "edge ab");
        assert!((d(DVec3::new(-1.0, 0.5, 0.0)) - 1.0).abs() < 1e-12, "edge ca");
        assert!((d(DVec3::new(1.0, 1.0, 0.0)) - 0.5).abs() < 1e-12, "edge bc");
    }

    #[test]
    fn min_angle_sine_is_the_sine_of_the_smallest_angle() {
        let triangles = [
            (DVec3::ZERO, DVec3::X, DVec3::Y),
            (DVec3::ZERO, DVec3::new(10.0, 0.0, 0.0), DVec3::new(3.0, 0.4, 0.0)),
            (DVec3::new(1.0, 2.0, 3.0), DVec3::new(-2.0, 0.5, 1.0), DVec3::new(0.3, -1.0, 2.0)),
        ];
        for (a, b, c) in triangles {
            assert!((min_angle_sine(a, b, c) - min_angle(a, b, c).sin()).abs() < 1e-12);
        }
        assert_eq!(min_angle_sine(DVec3::ZERO, DVec3::X, DVec3::X * 2.0), 0.0);
    }

    #[test]
    fn choose_prefers_shape_among_near_equal_costs() {
        let c = |index, cost, shape| Choice { index, cost, shape };
        assert_eq!(choose(&[c(0, 1.0, 0.1), c(1, 1.05, 0.5), c(2, 2.0, 1.0)], 0.0).unwrap().index, 1);
        assert_eq!(choose(&[c(0, 1.0, 0.1), c(1, 1.5, 0.5)], 0.0).unwrap().index, 0);
        assert!(choose(&[], 0.0).is_none());
    }

    #[test]
    fn spokes_cross_the_edges_that_replace_them() {
        let (t, s) = spoke_crossing(DVec2::new(2.0, 0.0), DVec2::new(1.0, -1.0), DVec2::new(1.0, 1.0)).unwrap();
        assert!((t - 0.5).abs() < 1e-12 && (s - 0.5).abs() < 1e-12);
        assert!(spoke_crossing(DVec2::new(0.5, 0.0), DVec2::new(1.0, -1.0), DVec2::new(1.0, 1.0)).is_none());
    }
}
