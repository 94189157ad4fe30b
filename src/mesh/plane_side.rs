//! A certified filter for triangle pairs: when one triangle's unshared corners lie strictly
//! on one side of the other's plane, the two meet at most in what they share, and no exact
//! test is needed (the first step of Möller's and of Guigue–Devillers' triangle tests). The
//! side is decided by Shewchuk's orient3d with its static error bound ("Adaptive precision
//! floating-point arithmetic and fast robust geometric predicates", 1997, bound A), so the
//! filter never rejects a pair that exact arithmetic would call intersecting; the pairs it
//! cannot certify go to CGAL's exact predicates. Pairs that share a corner, or lie in one
//! plane (flat regions of CAD parts), are also tried against planes through each edge,
//! standing across its triangle: a separating plane that holds the shared elements.

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
/// of the other's plane, or a plane through an edge of one, across that triangle, has the
/// triangle's third corner strictly on one side and the other triangle's corners off the
/// edge strictly on the other (`split_at_an_edge`). The edge planes are tried for pairs
/// that share a corner and for pairs that neither plane certainly cuts (coplanar or nearly
/// so): two triangles each of whose planes cuts the other mostly do cross, and testing
/// their edge planes would cost more than the exact test it saves.
pub fn certainly_apart(positions: &[DVec3], s: [u32; 3], t: [u32; 3]) -> bool {
    let t_against_s = one_side_of(positions, s, t);
    if t_against_s == Side::Apart {
        return true;
    }
    let s_against_t = one_side_of(positions, t, s);
    if s_against_t == Side::Apart {
        return true;
    }
    let sharing = s.iter().any(|v| t.contains(v));
    (sharing || (t_against_s != Side::Cut && s_against_t != Side::Cut))
        && (split_at_an_edge(positions, s, t) || split_at_an_edge(positions, t, s))
}

/// Where a triangle's corners lie against another's plane.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    /// Every unshared corner strictly on one side.
    Apart,
    /// Unshared corners strictly on both sides: the plane cuts the triangle.
    Cut,
    /// Neither certified (a corner on the plane or too close to tell).
    Unsure,
}

/// Where the corners of `t` not in `s` lie against the plane of `s`.
fn one_side_of(positions: &[DVec3], s: [u32; 3], t: [u32; 3]) -> Side {
    let [a, b, c] = s.map(|v| positions[v as usize]);
    let (mut side, mut unsure) = (0, false);
    for v in t {
        if s.contains(&v) {
            continue;
        }
        match certain_orientation(a, b, c, positions[v as usize]) {
            0 => unsure = true,
            o if side != 0 && o != side => return Side::Cut,
            o => side = o,
        }
    }
    if unsure || side == 0 { Side::Unsure } else { Side::Apart }
}

/// Whether a plane through an edge (a, b) of `s`, standing across `s` (it holds a point off
/// `s` along `s`'s normal), separates them: `s`'s third corner strictly on one side, every
/// corner of `t` other than a and b strictly on the other. `s` then meets the plane in its
/// edge and `t` in those of a and b it has, so the two meet at most there. Where `s` and `t`
/// are coplanar neighbours (flat regions of CAD parts) or a saddle's fan, neither lies on
/// one side of the other's plane and this plane is what tells them apart. The plane's third
/// point is rounded, but the test is orient3d's on the three points as they are, so a
/// rounded point only moves the plane, never the certainty.
fn split_at_an_edge(positions: &[DVec3], s: [u32; 3], t: [u32; 3]) -> bool {
    let p = s.map(|v| positions[v as usize]);
    let across = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
    (0..3).any(|i| {
        let (a, b, c) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
        let edge = [s[i], s[(i + 1) % 3]];
        let q = a + across * (b - a).length();
        let side = certain_orientation(a, b, q, c);
        let mut off_edge = t.iter().filter(|v| !edge.contains(v)).peekable();
        side != 0
            && off_edge.peek().is_some()
            && off_edge.all(|&v| certain_orientation(a, b, q, positions[v as usize]) == -side)
    })
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

    #[test]
    fn coplanar_neighbours_are_apart_only_beside_each_other() {
        let positions = [
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::new(0.5, -1.0, 0.0),  // 3: across edge 0-1, in the plane
            DVec3::new(-1.0, 0.2, 0.0),  // 4: across edge 0-2, in the plane
            DVec3::new(-1.0, -0.3, 0.0), // 5: beside 0, in the plane
            DVec3::new(0.3, 0.3, 0.0),   // 6: inside triangle 0 1 2
            DVec3::new(2.0, 2.0, 0.0),   // 7: beyond edge 1-2, in the plane
        ];
        // An edge shared, the third corners on either side of it: apart.
        assert!(certainly_apart(&positions, [0, 1, 2], [1, 0, 3]));
        // A corner shared, the other wedge beside this one: apart.
        assert!(certainly_apart(&positions, [0, 1, 2], [0, 4, 5]));
        assert!(certainly_apart(&positions, [0, 1, 2], [0, 5, 3]));
        // A corner shared, the wedges overlapping (4 to 3 sweeps over the triangle's corner): not certified.
        assert!(!certainly_apart(&positions, [0, 1, 2], [0, 3, 7]));
        assert!(!certainly_apart(&positions, [0, 1, 2], [0, 6, 4]));
        // An edge shared, the third corners on one side: not certified.
        assert!(!certainly_apart(&positions, [0, 1, 2], [1, 0, 6]));
        // No corner shared, in one plane: apart beside each other, not when one overlaps the other.
        assert!(certainly_apart(&positions, [0, 1, 2], [3, 5, 4]));
        assert!(!certainly_apart(&positions, [0, 1, 2], [6, 7, 3]));
        // A corner shared, the other triangle folded up across an edge: the edge's plane still splits them.
        let folded = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, -1.0, 0.5), DVec3::new(-1.0, -1.0, -0.5)];
        assert!(certainly_apart(&folded, [0, 1, 2], [0, 3, 4]));
    }
}
