//! A certified filter for triangle pairs: when one triangle's unshared corners lie strictly
//! on one side of the other's plane, the two meet at most in what they share, and no exact
//! test is needed (the first step of Möller's and of Guigue–Devillers' triangle tests). The
//! side is decided by Shewchuk's orient3d with its static error bound ("Adaptive precision
//! floating-point arithmetic and fast robust geometric predicates", 1997, bound A), so the
//! filter never rejects a pair that exact arithmetic would call intersecting; the pairs it
//! cannot certify go to CGAL's exact predicates.

use glam::DVec3;

/// Shewchuk's o3derrboundA: (7 + 56ε)ε with ε = 2⁻⁵³.
const ORIENT3D_BOUND: f64 = (7.0 + 56.0 * f64::EPSILON / 2.0) * f64::EPSILON / 2.0;

/// Below this permanent the products may underflow and the bound no longer holds.
const SMALLEST_PERMANENT: f64 = 1e-250;

/// The sign of orient3d(a, b, c, d) when the floating-point value certifies it (+1 or −1:
/// d below or above the plane of a, b, c), else 0.
pub fn certain_orientation(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> i32 {
    let (ad, bd, cd) = (a - d, b - d, c - d);
    let bc = bd.x * cd.y - cd.x * bd.y;
    let ca = cd.x * ad.y - ad.x * cd.y;
    let ab = ad.x * bd.y - bd.x * ad.y;
    let det = ad.z * bc + bd.z * ca + cd.z * ab;
    let permanent = ((bd.x * cd.y).abs() + (cd.x * bd.y).abs()) * ad.z.abs()
        + ((cd.x * ad.y).abs() + (ad.x * cd.y).abs()) * bd.z.abs()
        + ((ad.x * bd.y).abs() + (bd.x * ad.y).abs()) * cd.z.abs();
    // Also false for NaN.
    let trusted = permanent.is_finite() && permanent >= SMALLEST_PERMANENT;
    if !trusted {
        return 0;
    }
    let bound = ORIENT3D_BOUND * permanent;
    if det > bound {
        1
    } else if det < -bound {
        -1
    } else {
        0
    }
}

/// Whether triangles `s` and `t` (vertex ids over `positions`) certainly meet at most in
/// the vertices or edge they share: the unshared corners of one lie strictly on one side
/// of the other's plane.
pub fn certainly_apart(positions: &[DVec3], s: [u32; 3], t: [u32; 3]) -> bool {
    one_side_of(positions, s, t) || one_side_of(positions, t, s)
}

/// Whether the corners of `t` not in `s` lie strictly on one side of the plane of `s`.
fn one_side_of(positions: &[DVec3], s: [u32; 3], t: [u32; 3]) -> bool {
    let [a, b, c] = s.map(|v| positions[v as usize]);
    let mut side = 0;
    for v in t {
        if s.contains(&v) {
            continue;
        }
        let o = certain_orientation(a, b, c, positions[v as usize]);
        if o == 0 || (side != 0 && o != side) {
            return false;
        }
        side = o;
    }
    side != 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orientation_is_certified_only_off_the_plane() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        assert_eq!(certain_orientation(a, b, c, DVec3::new(0.2, 0.2, -1.0)), 1);
        assert_eq!(certain_orientation(a, b, c, DVec3::new(0.2, 0.2, 1.0)), -1);
        assert_eq!(certain_orientation(a, b, c, DVec3::new(5.0, -3.0, 0.0)), 0);
        // Rounding cannot be trusted this close: 1e-17 off a plane through 0.1-ish points.
        let (p, q, r) = (DVec3::new(0.1, 0.7, 0.3), DVec3::new(0.9, 0.2, 0.3), DVec3::new(0.4, 0.4, 0.3));
        assert_eq!(certain_orientation(p, q, r, DVec3::new(0.3, 0.3, 0.3 + 1e-17)), 0);
        assert_eq!(certain_orientation(a, b, c, DVec3::new(0.2, 0.2, f64::NAN)), 0);
    }

    #[test]
    fn pairs_are_apart_only_when_one_lies_on_one_side() {
        let positions = [
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::new(0.3, 0.3, 1.0),   // 3: above
            DVec3::new(0.3, 0.3, -1.0),  // 4: below
            DVec3::new(0.3, 0.3, 0.0),   // 5: in the plane, inside
            DVec3::new(-1.0, -1.0, 1.0), // 6: above
        ];
        // Sharing an edge, folded out of the plane: apart.
        assert!(certainly_apart(&positions, [0, 1, 2], [1, 0, 3]));
        // Sharing an edge and coplanar: not certified (CGAL decides).
        assert!(!certainly_apart(&positions, [0, 1, 2], [1, 0, 5]));
        // Sharing a vertex, the other two above: apart.
        assert!(certainly_apart(&positions, [0, 1, 2], [0, 3, 6]));
        // Sharing a vertex, piercing the plane: not certified.
        assert!(!certainly_apart(&positions, [0, 1, 2], [0, 3, 4]));
        // The same triangle: never apart.
        assert!(!certainly_apart(&positions, [0, 1, 2], [1, 2, 0]));
    }
}
