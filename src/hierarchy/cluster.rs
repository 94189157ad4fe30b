//! Planning one four-face cluster (thesis §3.1.7, §4.4.1; Velho & Gomes \[3\]): the spoke
//! flips that bring a vertex to degree 4, the edge weld that removes it, their errors
//! (eq. 4.1), and the MAPS data of the removal (§4.4.1.2).
//!
//! Every decision is made in the vertex's conformal flattening (see [`Flattening`]), so the
//! retriangulated ring is a valid planar triangulation containing the removed vertex:
//! point location then never fails. The plan also records what refinement needs to rebuild
//! the ring exactly: the weld's diagonal (the edge to split) and the flipped-away ring
//! vertices (the link edges to flip back, in order). The thesis' geometric rules —
//! Algorithm 2's nearest edge and Algorithm 3's widest angle — pick a different edge for
//! most clusters of a real mesh (measured: on bunny00, requiring them limits simplification
//! to 23 % of the vertices instead of reaching a tetrahedron), so refinement uses them only
//! where the recorded face no longer exists.

use glam::{DVec2, DVec3};
use smallvec::SmallVec;

use super::conformal::{Flattening, locate, orient};
use super::rings::{RingVec, Rings};
use crate::ffi::Quadric;

/// Weights and thresholds of the cluster selection.
#[derive(Debug, Clone, Copy)]
pub struct ClusterRules {
    /// Weight of the removal (weld) error in E(v) (eq. 4.1: 0.75).
    pub removal_weight: f64,
    /// Weight of the swap (flip) error in E(v) (eq. 4.1: 0.25).
    pub swap_weight: f64,
}

/// Positions and accumulated quadrics of the current level.
#[derive(Debug, Clone, Copy)]
pub struct LevelGeometry<'a> {
    /// Vertex positions (never moved by simplification).
    pub positions: &'a [DVec3],
    /// Garland–Heckbert quadrics, accumulated over removed vertices.
    pub quadrics: &'a [Quadric],
}

/// A planned removal of one vertex.
#[derive(Debug, Clone)]
pub struct ClusterPlan {
    /// The removed vertex.
    pub vertex: u32,
    /// Its 1-ring before the flips (the level's connectivity).
    pub ring: RingVec<u32>,
    /// Ring vertices whose spoke is flipped away, in flip order (refinement flips them
    /// back in reverse order).
    pub flips: SmallVec<[u32; 4]>,
    /// The weld: the vertex collapses onto this ring vertex.
    pub weld_to: u32,
    /// The edge the weld creates (refinement splits it to re-insert the vertex).
    pub diagonal: [u32; 2],
    /// The retriangulated ring polygon (ears of the flips, then the two weld triangles),
    /// counter-clockwise.
    pub triangles: SmallVec<[[u32; 3]; 6]>,
    /// The triangle (index into `triangles`) containing the removed vertex, and its
    /// barycentric coordinates there.
    pub location: (usize, [f64; 3]),
    /// E(v) = α·removal error + β·swap error.
    pub error: f64,
}

impl ClusterPlan {
    /// The ring's conformal flattening (the vertex at the origin), as planning computed
    /// it: recomputed from the positions when needed, so a level's plans stay small while
    /// the recorder holds them.
    pub fn flattening(&self, positions: &[DVec3]) -> RingVec<DVec2> {
        let ring_points: RingVec<DVec3> = self.ring.iter().map(|&r| positions[r as usize]).collect();
        Flattening::of_closed_ring(positions[self.vertex as usize], &ring_points)
            .map(|f| f.points)
            .unwrap_or_else(|| smallvec::smallvec![DVec2::ZERO; self.ring.len()])
    }

    /// The planar image of vertex `id` in `flat` (the plan's flattening): the removed
    /// vertex at the origin, a ring vertex at its flattened point.
    pub fn image(&self, id: u32, flat: &[DVec2]) -> DVec2 {
        self.ring.iter().position(|&r| r == id).map_or(DVec2::ZERO, |j| flat[j])
    }

    /// Planar images of `triangles` in `flat` (the plan's flattening).
    pub fn flat_triangles(&self, flat: &[DVec2]) -> RingVec<[DVec2; 3]> {
        self.triangles.iter().map(|t| t.map(|id| self.image(id, flat))).collect()
    }
}

/// Cheap estimate of E(v) used to order the candidates of a level: the removal error
/// along the best "opposite" diagonal plus the cheapest d − 4 spoke flips.
pub fn estimate_error(v: u32, rings: &Rings, geometry: LevelGeometry<'_>, rules: &ClusterRules) -> f64 {
    let ring = rings.ring(v);
    let d = ring.len();
    let pos = geometry.positions;
    let q = &geometry.quadrics[v as usize];
    let removal = (0..d.div_ceil(2))
        .map(|k| q.error((pos[ring[k] as usize] + pos[ring[(k + d / 2) % d] as usize]) * 0.5))
        .fold(f64::INFINITY, f64::min);
    let mut swaps: RingVec<f64> = (0..d).map(|i| spoke_flip_error(v, ring, i, geometry)).collect();
    swaps.sort_by(f64::total_cmp);
    let swap: f64 = swaps.iter().take(d.saturating_sub(4)).sum();
    rules.removal_weight * removal + rules.swap_weight * swap
}

/// Error of flipping the spoke v–`ring[i]`: the new edge `ring[i−1]`–`ring[i+1]` measured at its
/// midpoint against the quadrics of the old edge's two endpoints.
fn spoke_flip_error(v: u32, ring: &[u32], i: usize, geometry: LevelGeometry<'_>) -> f64 {
    let d = ring.len();
    let pos = geometry.positions;
    let (prev, apex, next) = (ring[(i + d - 1) % d], ring[i], ring[(i + 1) % d]);
    let m = (pos[prev as usize] + pos[next as usize]) * 0.5;
    geometry.quadrics[v as usize].error(m) + geometry.quadrics[apex as usize].error(m)
}

fn normal(a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    (b - a).cross(c - a)
}

/// A triangle whose area is (relatively) zero: below 1e-8 of its longest edge squared, a
/// margin above the 1e-12 at which validation calls a face degenerate.
fn is_sliver(a: DVec3, b: DVec3, c: DVec3) -> bool {
    let longest = (b - a).length_squared().max((c - b).length_squared()).max((a - c).length_squared());
    normal(a, b, c).length() <= 1e-8 * longest
}

/// Index i of the edge (`t[i]`, `t[i+1]`) of a 3D triangle nearest to `p` (Algorithm 2 of
/// §4.6); ties go to the lower index.
pub fn nearest_edge(t: [DVec3; 3], p: DVec3) -> usize {
    let mut best = (0, f64::INFINITY);
    for i in 0..3 {
        let d = point_segment_distance_squared(p, t[i], t[(i + 1) % 3]);
        if d < best.1 {
            best = (i, d);
        }
    }
    best.0
}

pub(super) fn point_segment_distance_squared(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 { ((p - a).dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (a + ab * t - p).length_squared()
}

/// Algorithm 3's choice: the link edge (`ring[j]`, `ring[j+1]`) of a closed ring whose angle
/// at `centre` is widest, if that angle reaches `threshold`. Ties go to the edge with the
/// smaller vertex ids, so the choice does not depend on where the ring starts.
pub fn widest_link_edge(centre: DVec3, ring: &[u32], positions: &[DVec3], threshold: f64) -> Option<usize> {
    let m = ring.len();
    let mut best: Option<(usize, f64, [u32; 2])> = None;
    for j in 0..m {
        let (a, b) = (ring[j], ring[(j + 1) % m]);
        let angle = (positions[a as usize] - centre).angle_between(positions[b as usize] - centre);
        let key = [a.min(b), a.max(b)];
        let better = match best {
            None => true,
            Some((_, w, k)) => angle > w || (angle == w && key < k),
        };
        if better {
            best = Some((j, angle, key));
        }
    }
    best.filter(|&(_, w, _)| w >= threshold).map(|(j, _, _)| j)
}

/// Plans the removal of the interior vertex `v`, or `None` if no valid cluster exists.
pub fn plan_cluster(v: u32, rings: &Rings, geometry: LevelGeometry<'_>, rules: &ClusterRules) -> Option<ClusterPlan> {
    let ring = RingVec::from_slice(rings.ring(v));
    let d = ring.len();
    if d < 4 || rings.is_boundary(v) {
        return None;
    }
    let pos = geometry.positions;
    let p = |i: usize| pos[ring[i] as usize];
    let pv = pos[v as usize];
    let ring_points: RingVec<DVec3> = (0..d).map(p).collect();
    let flat = Flattening::of_closed_ring(pv, &ring_points)?.points;

    // Spoke flips, cheapest valid first, until the degree is 4.
    let mut current: RingVec<usize> = (0..d).collect();
    let mut gain: RingVec<i64> = smallvec::smallvec![0; d];
    let mut ears: RingVec<[usize; 3]> = RingVec::new();
    let mut swap_error = 0.0;
    while current.len() > 4 {
        let m = current.len();
        let mut best: Option<(usize, f64)> = None;
        for i in 0..m {
            let (prev, apex, next) = (current[(i + m - 1) % m], current[i], current[(i + 1) % m]);
            if rings.has_edge(ring[prev], ring[next])
                || rings.degree(ring[apex]) as i64 + gain[apex] - 1 < 3
                || orient(flat[prev], flat[apex], flat[next]) <= 0.0
                || orient(DVec2::ZERO, flat[prev], flat[next]) <= 0.0
            {
                continue;
            }
            let ear = normal(p(prev), p(apex), p(next));
            if is_sliver(p(prev), p(apex), p(next))
                || ear.dot(normal(pv, p(prev), p(apex))) <= 0.0
                || ear.dot(normal(pv, p(apex), p(next))) <= 0.0
            {
                continue;
            }
            let m3 = (p(prev) + p(next)) * 0.5;
            let cost = geometry.quadrics[v as usize].error(m3) + geometry.quadrics[ring[apex] as usize].error(m3);
            if best.is_none_or(|(_, c)| cost < c) {
                best = Some((i, cost));
            }
        }
        let (i, cost) = best?;
        let m = current.len();
        let (prev, apex, next) = (current[(i + m - 1) % m], current[i], current[(i + 1) % m]);
        gain[apex] -= 1;
        gain[prev] += 1;
        gain[next] += 1;
        ears.push([prev, apex, next]);
        current.remove(i);
        swap_error += cost;
    }

    // The weld: the cheaper of the two diagonals that keeps the ring valid.
    let mut options: SmallVec<[(f64, usize); 2]> = SmallVec::new();
    for k in 0..2 {
        let c = [current[k], current[k + 1], current[(k + 2) % 4], current[(k + 3) % 4]];
        if rings.has_edge(ring[c[0]], ring[c[2]])
            || rings.degree(ring[c[1]]) as i64 + gain[c[1]] - 1 < 3
            || rings.degree(ring[c[3]]) as i64 + gain[c[3]] - 1 < 3
            || orient(flat[c[0]], flat[c[1]], flat[c[2]]) <= 0.0
            || orient(flat[c[0]], flat[c[2]], flat[c[3]]) <= 0.0
        {
            continue;
        }
        if is_sliver(p(c[0]), p(c[1]), p(c[2])) || is_sliver(p(c[0]), p(c[2]), p(c[3])) {
            continue;
        }
        let t0 = normal(p(c[0]), p(c[1]), p(c[2]));
        let t1 = normal(p(c[0]), p(c[2]), p(c[3]));
        if t0.dot(normal(pv, p(c[1]), p(c[2]))) <= 0.0 || t1.dot(normal(pv, p(c[2]), p(c[3]))) <= 0.0 {
            continue;
        }
        let removal = geometry.quadrics[v as usize].error((p(c[0]) + p(c[2])) * 0.5);
        options.push((rules.removal_weight * removal + rules.swap_weight * swap_error, k));
    }
    options.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    if let Some(&(error, k)) = options.first() {
        let c = [current[k], current[k + 1], current[(k + 2) % 4], current[(k + 3) % 4]];
        let mut triangles = ears.clone();
        triangles.push([c[0], c[1], c[2]]);
        triangles.push([c[0], c[2], c[3]]);
        let n = triangles.len();
        let weld_images = [[c[0], c[1], c[2]], [c[0], c[2], c[3]]].map(|t| t.map(|i| flat[i]));
        let (t, w) = locate(DVec2::ZERO, &weld_images);
        return Some(ClusterPlan {
            vertex: v,
            flips: ears.iter().map(|e| ring[e[1]]).collect(),
            weld_to: ring[c[0]],
            diagonal: [ring[c[0]], ring[c[2]]],
            triangles: triangles.iter().map(|t| t.map(|i| ring[i])).collect(),
            location: (n - 2 + t, w),
            error,
            ring,
        });
    }
    None
}

/// Whether `plan`, made on an earlier state of the rings, can still be carried out: the
/// vertex has the same ring, no flip or weld would create an edge that now exists, and no
/// ring vertex would drop below degree 3 (the topological conditions of [`plan_cluster`];
/// its geometric ones depend on positions only). Used when a level drops some of its plans
/// and replays the others.
pub fn plan_still_applies(plan: &ClusterPlan, rings: &Rings) -> bool {
    if rings.ring(plan.vertex) != plan.ring.as_slice() {
        return false;
    }
    let mut gain: RingVec<i64> = smallvec::smallvec![0; plan.ring.len()];
    let slot = |id: u32| plan.ring.iter().position(|&r| r == id).expect("a ring vertex");
    let drops_too_low = |id: u32, gain: &[i64]| rings.degree(id) as i64 + gain[slot(id)] - 1 < 3;
    let (ears, weld) = plan.triangles.split_at(plan.flips.len());
    for &[prev, apex, next] in ears {
        if rings.has_edge(prev, next) || drops_too_low(apex, &gain) {
            return false;
        }
        gain[slot(apex)] -= 1;
        gain[slot(prev)] += 1;
        gain[slot(next)] += 1;
    }
    let ([c0, c1, c2], [_, _, c3]) = (weld[0], weld[1]);
    !(rings.has_edge(c0, c2) || drops_too_low(c1, &gain) || drops_too_low(c3, &gain))
}

/// Carries out `plan` on the rings: its spoke flips, then its weld.
///
/// # Errors
/// [`Error::Internal`](crate::Error::Internal) if the rings do not allow it (a plan that
/// no longer applies).
pub fn apply_plan(plan: &ClusterPlan, rings: &mut Rings) -> crate::Result<()> {
    for &apex in &plan.flips {
        rings.flip(plan.vertex, apex)?;
    }
    rings.weld(plan.vertex, plan.weld_to)
}
