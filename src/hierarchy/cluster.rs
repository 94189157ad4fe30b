//! Planning one four-face cluster (thesis §3.1.7, §4.4.1; Velho & Gomes \[3\]): the spoke
//! flips that bring a vertex to degree 4 (3 on a boundary), the edge weld that removes it,
//! their errors (eq. 4.1, measured as in [`super::cost`]), and the MAPS data of the
//! removal (§4.4.1.2).
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

use super::conformal::{Flattening, Located, interpolate, locate, locate_from, orient};
use super::cost::{
    Choice, choose, crossing_error, min_angle_sine, point_segment_distance_squared, point_triangle_distance_squared,
    spoke_crossing,
};
use super::lines::FeatureLines;
use super::param::{ParamBuckets, PointPositions};
use super::plan::ClusterPlan;
use super::rings::{RingVec, Rings};
use super::vertex_table::VertexTable;
use crate::analysis::Quadric;

/// Weights and thresholds of the cluster selection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClusterRules {
    /// Weight of the removal (weld) error in E(v) (eq. 4.1: 0.75).
    pub removal_weight: f64,
    /// Weight of the swap (flip) error in E(v) (eq. 4.1: 0.25).
    pub swap_weight: f64,
    /// Smallest angle (radians) a cluster's new triangles may have, unless the star they
    /// replace already had a smaller one.
    pub min_angle: f64,
    /// Whether a cluster with none at `min_angle` may go down to
    /// `cluster::NEARLY_FREE_FLOOR_DEGREES`, at `give_way::FEATURE_PREMIUM` (while the level's slivers
    /// stay within the input's share: `sliver_budget`).
    pub under_floor: bool,
}

/// Positions and accumulated quadrics of the current level.
#[derive(Debug, Clone, Copy)]
pub struct LevelGeometry<'a> {
    /// The positions of the level's vertices (`points.own`: never moved by
    /// simplification) and of its parametrized points.
    pub points: PointPositions<'a>,
    /// Garland–Heckbert quadrics, accumulated over removed vertices.
    pub quadrics: &'a VertexTable<Quadric>,
    /// Errors closer than this (a squared distance far below the model's size) are equal.
    pub tolerance: f64,
    /// Where the vertices removed so far lie on the level's faces.
    pub params: &'a ParamBuckets,
    /// The level's feature lines.
    pub lines: &'a FeatureLines,
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
///
/// The flips and the weld are chosen by the error they really introduce (see
/// [`super::cost`]): each removed spoke is measured where the edge that replaces it
/// crosses it, and the removed vertex and every vertex parametrized onto its star against
/// the new triangle its parameter point lands on. Costs within [`LevelGeometry::tolerance`]
/// or 10 % of the cheapest are equal, and the shape of the triangles made (their smallest
/// angle) decides among them; a plan whose triangles have a smaller angle than
/// [`ClusterRules::min_angle`] and than the star it replaces is refused.
///
/// The flips are first chosen greedily, cheapest first. Where that leads to no valid weld,
/// the fans of the ring (the triangulations a half-edge collapse onto one ring vertex
/// makes, reached by cutting the ears farthest from that vertex first) are tried, and the
/// cheapest valid one is kept.
pub fn plan_cluster(v: u32, rings: &Rings, geometry: LevelGeometry<'_>, rules: &ClusterRules) -> Option<ClusterPlan> {
    plan_cluster_with(v, rings, geometry, rules, false)
}

/// [`plan_cluster`] for `v` as if it were released from its feature lines (`free`): an
/// inside vertex planned like a surface vertex, a boundary vertex along its boundary
/// alone. What the give-way ladder measures before it releases a feature vertex.
pub fn plan_cluster_with(
    v: u32,
    rings: &Rings,
    geometry: LevelGeometry<'_>,
    rules: &ClusterRules,
    free: bool,
) -> Option<ClusterPlan> {
    let ring = RingVec::from_slice(rings.ring(v));
    let d = ring.len();
    let boundary = rings.is_boundary(v);
    if d < if boundary { 3 } else { 4 } {
        return None;
    }
    let pos = geometry.points.own;
    let pv = pos[v as usize];
    let ring_points: RingVec<DVec3> = ring.iter().map(|&r| pos[r as usize]).collect();
    let flat = Flattening::of_star(pv, &ring_points, boundary)?.points;
    let faces = if boundary { d - 1 } else { d };
    let line = match (free, geometry.lines.neighbours(v, rings)) {
        (true, _) if boundary => Some(([0, d - 1], geometry.lines.bound_between(v, ring[0], ring[d - 1]))),
        (true, _) => None,
        (false, Some((ends, bound))) => {
            Some((ends.map(|e| ring.iter().position(|&r| r == e).expect("a ring vertex")), bound))
        }
        (false, None) if geometry.lines.is_on_line(v) || boundary => return None,
        (false, None) => None,
    };
    // A boundary vertex goes along its boundary: its line neighbours are its ring's ends.
    if boundary && line.is_none_or(|([a, b], _)| [a.min(b), a.max(b)] != [0, d - 1]) {
        return None;
    }
    let floor = ShapeFloor { rule: rules.min_angle.sin(), star: std::cell::Cell::new(None), faces };
    let points_on_star = std::cell::OnceCell::new();
    let mut star =
        Star { v, ring, points: ring_points, flat, rings, geometry, rules, floor, points_on_star, line, boundary };
    if let Some(plan) = star.best_plan() {
        return Some(plan);
    }
    // No cluster at the floor: one down to the nearly-free floor, at the premium a feature
    // vertex pays (#34), so it is taken only where it moves the surface at most half as far
    // as the level allows elsewhere. On sliver-ridden CAD output the 5° floor otherwise
    // leaves a flat face's vertices without a cluster while the level removes dearer ones
    // (tardis at 25 %: 79 of 462 vertices without one).
    let soft = NEARLY_FREE_FLOOR_DEGREES.to_radians();
    if !rules.under_floor || rules.min_angle <= soft {
        return None;
    }
    star.floor.rule = soft.sin();
    star.best_plan().map(|plan| ClusterPlan { error: plan.error * FEATURE_PREMIUM, under_floor: true, ..plan })
}

/// How much cheaper than the level's error limit (a squared distance) a feature vertex's
/// removal must be before the level releases it (`give_way`), and what a cluster below the
/// angle floor pays: 4, so either is taken only where it moves the surface at most half as
/// far as the level allows elsewhere.
pub(super) const FEATURE_PREMIUM: f64 = 4.0;

/// The smallest angle a cluster may make below the angle floor, degrees: 0.5, the
/// smallest angle #34 asks of any mesh whose input has none smaller.
pub const NEARLY_FREE_FLOOR_DEGREES: f64 = 0.5;

impl Star<'_> {
    /// The cheapest plan at the star's floor: greedy spoke flips, else the cheapest fan.
    fn best_plan(&self) -> Option<ClusterPlan> {
        if let Some(plan) = self.greedy_ears().and_then(|ears| self.weld(ears)) {
            return Some(plan);
        }
        let d = self.ring.len();
        let fans = if self.boundary { 1..d - 1 } else { 0..d };
        fans.filter_map(|j| self.fan_ears(j).and_then(|ears| self.weld(ears)))
            .min_by(|a, b| a.error.total_cmp(&b.error))
    }
}

/// A vertex's star while its cluster is planned.
struct Star<'a> {
    v: u32,
    ring: RingVec<u32>,
    /// The ring's 3D positions.
    points: RingVec<DVec3>,
    /// The ring's conformal flattening (the vertex at the origin).
    flat: RingVec<DVec2>,
    rings: &'a Rings,
    geometry: LevelGeometry<'a>,
    rules: &'a ClusterRules,
    /// The smallest angle the cluster may make.
    floor: ShapeFloor,
    /// The vertices parametrized onto the star, once needed.
    points_on_star: std::cell::OnceCell<StarPoints>,
    /// For a vertex on a feature line: the ring slots of its two line neighbours (their
    /// spokes are never flipped and the diagonal joins them) and the larger bound of its
    /// two feature edges.
    line: Option<([usize; 2], f64)>,
    /// Whether the ring is open (a boundary vertex).
    boundary: bool,
}

/// The ring polygon after some ear cuts (spoke flips): the remaining ring slots, each
/// slot's degree change, the ears cut and their summed error.
#[derive(Clone)]
struct Ears {
    current: RingVec<usize>,
    gain: RingVec<i64>,
    cut: RingVec<[usize; 3]>,
    swap_error: f64,
}

/// The sine of the smallest angle a cluster may make: the rule's, or the star's own
/// smallest where that is smaller. The star's is measured only when a shape falls below the
/// rule's (most never do), so planning skips it.
struct ShapeFloor {
    rule: f64,
    star: std::cell::Cell<Option<f64>>,
    faces: usize,
}

impl Star<'_> {
    /// The vertices parametrized onto the star (see [`star_points`]), gathered once per
    /// star however many welds are tried.
    fn star_points(&self) -> &StarPoints {
        self.points_on_star.get_or_init(|| star_points(self.v, &self.ring, &self.flat, self.geometry, self.boundary))
    }

    /// Whether `shape` (a sine) is below the floor.
    fn below_floor(&self, shape: f64) -> bool {
        if shape >= self.floor.rule {
            return false;
        }
        let star = self.floor.star.get().unwrap_or_else(|| {
            let (pv, p, d) = (self.pv(), &self.points, self.ring.len());
            let least = (0..self.floor.faces).map(|i| min_angle_sine(pv, p[i], p[(i + 1) % d])).fold(1.0, f64::min);
            self.floor.star.set(Some(least));
            least
        });
        shape < star
    }

    fn pv(&self) -> DVec3 {
        self.geometry.points.own[self.v as usize]
    }

    /// For a line vertex welded along the diagonal between ring slots `a` and `b` (its
    /// line neighbours): the new feature edge's bound, the old edges' bound plus the
    /// vertex's distance from the new edge.
    fn line_bound(&self, a: usize, b: usize) -> Option<f64> {
        let (_, bound) = self.line?;
        Some(bound + point_segment_distance_squared(self.pv(), self.points[a], self.points[b]).sqrt())
    }

    /// The degree the flips bring the vertex to: 4 inside, 3 on a boundary.
    fn weld_degree(&self) -> usize {
        if self.boundary { 3 } else { 4 }
    }

    /// The ear positions of a polygon of `m` slots: all inside, the inner ones on a
    /// boundary (the open ring's ends are never apexes).
    fn ear_positions(&self, m: usize) -> std::ops::Range<usize> {
        if self.boundary { 1..m - 1 } else { 0..m }
    }

    fn start(&self) -> Ears {
        let d = self.ring.len();
        Ears { current: (0..d).collect(), gain: smallvec::smallvec![0; d], cut: RingVec::new(), swap_error: 0.0 }
    }

    /// The ear at position `i` of the current polygon, if cutting it (flipping its spoke)
    /// is valid: its error and shape.
    fn ear(&self, ears: &Ears, i: usize) -> Option<Choice> {
        let (ring, flat, p) = (&self.ring, &self.flat, &self.points);
        let m = ears.current.len();
        let (prev, apex, next) = (ears.current[(i + m - 1) % m], ears.current[i], ears.current[(i + 1) % m]);
        if self.line.is_some_and(|(ends, _)| ends.contains(&apex))
            || !self.rings.may_join(ring[prev], ring[next])
            || !self.rings.may_lose_neighbour(ring[apex], ears.gain[apex])
            || orient(flat[prev], flat[apex], flat[next]) <= 0.0
            || orient(DVec2::ZERO, flat[prev], flat[next]) <= 0.0
        {
            return None;
        }
        let pv = self.pv();
        let ear = normal(p[prev], p[apex], p[next]);
        if is_sliver(p[prev], p[apex], p[next])
            || ear.dot(normal(pv, p[prev], p[apex])) <= 0.0
            || ear.dot(normal(pv, p[apex], p[next])) <= 0.0
        {
            return None;
        }
        let shape = min_angle_sine(p[prev], p[apex], p[next]);
        if self.below_floor(shape) {
            return None;
        }
        let (_, s) = spoke_crossing(flat[apex], flat[prev], flat[next]).unwrap_or((0.5, 0.5));
        let cost = crossing_error(pv, p[prev], p[apex], p[next], p[prev].lerp(p[next], s));
        Some(Choice { index: i, cost, shape })
    }

    /// Cuts the ear at position `i`.
    fn cut(ears: &mut Ears, choice: Choice) {
        let m = ears.current.len();
        let i = choice.index;
        let (prev, apex, next) = (ears.current[(i + m - 1) % m], ears.current[i], ears.current[(i + 1) % m]);
        ears.gain[apex] -= 1;
        ears.gain[prev] += 1;
        ears.gain[next] += 1;
        ears.cut.push([prev, apex, next]);
        ears.current.remove(i);
        ears.swap_error += choice.cost;
    }

    /// Spoke flips until the degree is 4: the cheapest valid one each time, shape breaking
    /// near-ties.
    ///
    /// An ear depends only on its own corners and their degree changes, so after a cut only
    /// the two ears beside it are evaluated again (the others are kept, by apex slot).
    fn greedy_ears(&self) -> Option<Ears> {
        let mut ears = self.start();
        let mut known: RingVec<Option<Option<(f64, f64)>>> = smallvec::smallvec![None; self.ring.len()];
        while ears.current.len() > self.weld_degree() {
            let choices: RingVec<Choice> = self
                .ear_positions(ears.current.len())
                .filter_map(|i| {
                    let slot = &mut known[ears.current[i]];
                    let ear = *slot.get_or_insert_with(|| self.ear(&ears, i).map(|c| (c.cost, c.shape)));
                    ear.map(|(cost, shape)| Choice { index: i, cost, shape })
                })
                .collect();
            let choice = choose(&choices, self.geometry.tolerance)?;
            let m = ears.current.len();
            let (prev, next) = (ears.current[(choice.index + m - 1) % m], ears.current[(choice.index + 1) % m]);
            known[prev] = None;
            known[next] = None;
            Self::cut(&mut ears, choice);
        }
        Some(ears)
    }

    /// The ear cuts that leave the fan of ring slot `j` (inside: the ears farthest from
    /// it first; on a boundary, `j` is the ring vertex left with the two ends, and the
    /// ears are cut from both ends towards it).
    fn fan_ears(&self, j: usize) -> Option<Ears> {
        let d = self.ring.len();
        let apexes: RingVec<usize> = match self.boundary {
            true => (1..j).chain((j + 1..d - 1).rev()).collect(),
            false => (1..=d - 4).map(|k| (j + d - k) % d).collect(),
        };
        let mut ears = self.start();
        for apex in apexes {
            let i = ears.current.iter().position(|&c| c == apex)?;
            let choice = self.ear(&ears, i)?;
            Self::cut(&mut ears, choice);
        }
        Some(ears)
    }

    /// The weld closing `ears` (a quadrilateral left): of its two diagonals that keep the
    /// ring valid, the one whose removal error (the mapped vertices, the vertex's image
    /// against its quadric, the diagonal where it crosses a spoke) is lower.
    fn weld(&self, ears: Ears) -> Option<ClusterPlan> {
        if self.boundary {
            return self.weld_boundary(ears);
        }
        let (ring, flat, p, rings) = (&self.ring, &self.flat, &self.points, self.rings);
        let (current, gain) = (&ears.current, &ears.gain);
        let pv = self.pv();
        let mut choices: RingVec<Choice> = RingVec::new();
        let mut located = [None; 2];
        // Where the star's points land among the ears: the same for both diagonals.
        let mut on_ears: Option<EarPlaces> = None;
        for k in 0..2 {
            let c = [current[k], current[k + 1], current[(k + 2) % 4], current[(k + 3) % 4]];
            if self.line.is_some_and(|([a, b], _)| [a.min(b), a.max(b)] != [c[0].min(c[2]), c[0].max(c[2])])
                || !rings.may_join(ring[c[0]], ring[c[2]])
                || !self.rings.may_lose_neighbour(ring[c[1]], gain[c[1]])
                || !self.rings.may_lose_neighbour(ring[c[3]], gain[c[3]])
                || orient(flat[c[0]], flat[c[1]], flat[c[2]]) <= 0.0
                || orient(flat[c[0]], flat[c[2]], flat[c[3]]) <= 0.0
            {
                continue;
            }
            if is_sliver(p[c[0]], p[c[1]], p[c[2]]) || is_sliver(p[c[0]], p[c[2]], p[c[3]]) {
                continue;
            }
            let t0 = normal(p[c[0]], p[c[1]], p[c[2]]);
            let t1 = normal(p[c[0]], p[c[2]], p[c[3]]);
            if t0.dot(normal(pv, p[c[1]], p[c[2]])) <= 0.0 || t1.dot(normal(pv, p[c[2]], p[c[3]])) <= 0.0 {
                continue;
            }
            let shape = min_angle_sine(p[c[0]], p[c[1]], p[c[2]]).min(min_angle_sine(p[c[0]], p[c[2]], p[c[3]]));
            if self.below_floor(shape) {
                continue;
            }
            let weld = [[c[0], c[1], c[2]], [c[0], c[2], c[3]]];
            let (t, w) = locate(DVec2::ZERO, &weld.map(|t| t.map(|i| flat[i])));
            located[k] = Some((t, w));
            let image = interpolate(weld[t].map(|i| p[i]), w);
            let points = self.star_points();
            let on_ears = on_ears.get_or_insert_with(|| EarPlaces::of(points, flat, &ears.cut));
            let mapped = on_ears.mapped_error(points, ring, flat, &weld, self.geometry.points);
            let mut removal = self.geometry.quadrics[self.v as usize].mean_error(image).max(mapped);
            if let Some(bound) = self.line_bound(c[0], c[2]) {
                removal = removal.max(bound * bound);
            }
            for [before, side, after] in [[c[0], c[1], c[2]], [c[2], c[3], c[0]]] {
                if let Some((_, s)) = spoke_crossing(flat[side], flat[c[0]], flat[c[2]]) {
                    removal += crossing_error(pv, p[before], p[side], p[after], p[c[0]].lerp(p[c[2]], s));
                }
            }
            let cost = self.rules.removal_weight * removal + self.rules.swap_weight * ears.swap_error;
            choices.push(Choice { index: k, cost, shape });
        }
        let Choice { index: k, cost: error, .. } = choose(&choices, self.geometry.tolerance)?;
        let c = [current[k], current[k + 1], current[(k + 2) % 4], current[(k + 3) % 4]];
        let along_line = self.line_bound(c[0], c[2]).map(|bound| ([ring[c[0]], ring[c[2]]], bound));
        let location = located[k].expect("a chosen diagonal was located");
        Some(self.plan(&ears, &[[c[0], c[1], c[2]], [c[0], c[2], c[3]]], location, error, along_line))
    }

    /// The plan of `ears` closed by the `weld` triangles (ring slots; the first one's first
    /// and last corners are the diagonal, welded onto the first), with the removed vertex
    /// at `location` (weld triangle, barycentric coordinates).
    fn plan(
        &self,
        ears: &Ears,
        weld: &[[usize; 3]],
        location: (usize, [f64; 3]),
        error: f64,
        along_line: Option<([u32; 2], f64)>,
    ) -> ClusterPlan {
        let ring = &self.ring;
        let [c0, _, c2] = weld[0];
        ClusterPlan {
            vertex: self.v,
            ring: ring.clone(),
            boundary: self.boundary,
            flips: ears.cut.iter().map(|e| ring[e[1]]).collect(),
            weld_to: ring[c0],
            diagonal: [ring[c0], ring[c2]],
            triangles: ears.cut.iter().chain(weld).map(|t| t.map(|i| ring[i])).collect(),
            location: (ears.cut.len() + location.0, location.1),
            error,
            along_line,
            under_floor: false,
        }
    }

    /// The weld of a boundary vertex brought to degree 3 (ring b0, r, b1): one triangle
    /// (b0, r, b1) left, b0–b1 the new boundary edge. Its removal error is that of the
    /// mapped vertices, of the vertex's image on b0–b1 against its quadric (whose planes
    /// include CGAL's boundary planes), and the boundary's distance bound.
    fn weld_boundary(&self, ears: Ears) -> Option<ClusterPlan> {
        let (ring, flat, p, rings) = (&self.ring, &self.flat, &self.points, self.rings);
        let c = [ears.current[0], ears.current[1], ears.current[2]];
        let pv = self.pv();
        if !rings.may_join(ring[c[0]], ring[c[2]])
            || !self.rings.may_lose_neighbour(ring[c[1]], ears.gain[c[1]])
            || orient(flat[c[0]], flat[c[1]], flat[c[2]]) <= 0.0
            || is_sliver(p[c[0]], p[c[1]], p[c[2]])
        {
            return None;
        }
        let t = normal(p[c[0]], p[c[1]], p[c[2]]);
        if t.dot(normal(pv, p[c[0]], p[c[1]])) <= 0.0 || t.dot(normal(pv, p[c[1]], p[c[2]])) <= 0.0 {
            return None;
        }
        let shape = min_angle_sine(p[c[0]], p[c[1]], p[c[2]]);
        if self.below_floor(shape) {
            return None;
        }
        let (_, w) = locate(DVec2::ZERO, &[c.map(|i| flat[i])]);
        let image = interpolate(c.map(|i| p[i]), w);
        let mut made: RingVec<[usize; 3]> = ears.cut.clone();
        made.push(c);
        let points = self.star_points();
        let mapped = mapped_error(points, ring, flat, &made, self.geometry.points);
        let bound = self.line_bound(c[0], c[2])?;
        let removal = self.geometry.quadrics[self.v as usize].mean_error(image).max(mapped).max(bound * bound);
        let error = self.rules.removal_weight * removal + self.rules.swap_weight * ears.swap_error;
        Some(self.plan(&ears, &[c], (0, w), error, Some(([ring[c[0]], ring[c[2]]], bound))))
    }
}

/// The vertices parametrized onto `v`'s star that lie farthest from their faces, with
/// their images in the flattening `flat` (the removed vertex itself first, at the origin).
fn star_points(v: u32, ring: &[u32], flat: &[DVec2], geometry: LevelGeometry<'_>, boundary: bool) -> StarPoints {
    let mut points: StarPoints = smallvec::smallvec![(v, DVec2::ZERO)];
    let d = ring.len();
    for k in 0..if boundary { d - 1 } else { d } {
        let corners = [(v, DVec2::ZERO), (ring[k], flat[k]), (ring[(k + 1) % d], flat[(k + 1) % d])];
        let image_of = |id: u32| corners.iter().find(|c| c.0 == id).map_or(DVec2::ZERO, |c| c.1);
        geometry.params.for_each_farthest_on([v, ring[k], ring[(k + 1) % d]], |w, point| {
            let image = point.face.iter().zip(point.bary).fold(DVec2::ZERO, |acc, (&id, b)| acc + image_of(id) * b);
            points.push((w, image));
        });
    }
    points
}

/// Vertices with their images in a star's flattening.
type StarPoints = SmallVec<[(u32, DVec2); 16]>;

/// Where each of a star's points lands among the ears a weld keeps (ring-index triples cut
/// before it), as [`locate`] searches: the ear so far with its coordinates, and the point's
/// squared distance from that ear once measured. Both diagonals of a weld continue the
/// same search over their own two triangles ([`locate_from`]; the ears come first in the
/// new triangles, so the result is [`mapped_error`]'s over all of them), and a point that
/// stays in an ear is measured once.
struct EarPlaces {
    ears: RingVec<[usize; 3]>,
    places: SmallVec<[(Located, Option<f64>); 16]>,
}

impl EarPlaces {
    fn of(points: &StarPoints, flat: &[DVec2], ears: &[[usize; 3]]) -> Self {
        let flat_ears: RingVec<[DVec2; 3]> = ears.iter().map(|t| t.map(|i| flat[i])).collect();
        let start = (0, [1.0, 0.0, 0.0], f64::NEG_INFINITY);
        let places = points.iter().map(|&(_, image)| (locate_from(image, &flat_ears, 0, start), None)).collect();
        EarPlaces { ears: ears.into(), places }
    }

    /// [`mapped_error`] over the ears then the `weld`'s triangles.
    fn mapped_error(
        &mut self,
        points: &StarPoints,
        ring: &[u32],
        flat: &[DVec2],
        weld: &[[usize; 3]; 2],
        pos: PointPositions,
    ) -> f64 {
        let flat_weld = weld.map(|t| t.map(|i| flat[i]));
        let ears = &self.ears;
        let distance = |t: [usize; 3], p: DVec3| {
            let [a, b, c] = t.map(|i| pos.own[ring[i] as usize]);
            point_triangle_distance_squared(p, a, b, c)
        };
        points
            .iter()
            .zip(&mut self.places)
            .map(|(&(w, image), (on_ears, measured))| {
                let (t, _, _) = locate_from(image, &flat_weld, ears.len(), *on_ears);
                let p = pos.of(w);
                match ears.get(t) {
                    Some(&ear) => *measured.get_or_insert_with(|| distance(ear, p)),
                    None => distance(weld[t - ears.len()], p),
                }
            })
            .fold(0.0, f64::max)
    }
}

/// The largest squared distance from each of `points` to the new triangle (ring-index
/// triples `made`) its image lands on in the flattening.
fn mapped_error(points: &StarPoints, ring: &[u32], flat: &[DVec2], made: &[[usize; 3]], pos: PointPositions) -> f64 {
    let flat_made: RingVec<[DVec2; 3]> = made.iter().map(|t| t.map(|i| flat[i])).collect();
    points
        .iter()
        .map(|&(w, image)| {
            let (t, _) = locate(image, &flat_made);
            let [a, b, c] = made[t].map(|i| pos.own[ring[i] as usize]);
            point_triangle_distance_squared(pos.of(w), a, b, c)
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shared search over the ears, continued per diagonal, gives `mapped_error` over
    /// all new triangles bit for bit: for points inside, outside and on edges, with ears
    /// cut and without, and with a degenerate weld triangle (whose coordinates are NaN).
    #[test]
    fn ear_places_give_the_mapped_error_of_every_new_triangle() {
        let d = 7;
        let ring: Vec<u32> = (0..d as u32).collect();
        let flat: Vec<DVec2> = (0..d)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / d as f64;
                DVec2::new(a.cos(), a.sin()) * (1.0 + 0.1 * k as f64)
            })
            .collect();
        let mut pos: Vec<DVec3> = flat.iter().enumerate().map(|(k, p)| p.extend(0.05 * k as f64)).collect();
        let mut points: StarPoints = SmallVec::new();
        for i in 0..40u32 {
            let image = DVec2::new((i as f64 * 0.37).sin(), (i as f64 * 0.71).cos()) * 1.3;
            points.push((pos.len() as u32, image));
            pos.push(image.extend(0.3 * (i as f64).cos()));
        }
        // Images on ring vertices lie on several triangles at once: ties, which the first
        // triangle in the new triangles' order wins.
        for k in [1, 0, 3, 4, 6] {
            points.push((pos.len() as u32, flat[k]));
            pos.push(DVec3::new(0.2, 0.1 * k as f64, 0.4));
        }
        let ears = [[0, 1, 2], [0, 2, 3], [4, 5, 6]];
        let welds = [[[0, 3, 4], [0, 4, 6]], [[3, 4, 4], [0, 3, 6]], [[3, 4, 4], [6, 6, 0]]];
        for cut in [&ears[..], &ears[..0]] {
            let mut places = EarPlaces::of(&points, &flat, cut);
            let pos = PointPositions { own: &pos, seeded: None };
            for weld in welds {
                let made: Vec<[usize; 3]> = cut.iter().copied().chain(weld).collect();
                let all = mapped_error(&points, &ring, &flat, &made, pos);
                let shared = places.mapped_error(&points, &ring, &flat, &weld, pos);
                assert_eq!(shared.to_bits(), all.to_bits(), "{} ears, weld {weld:?}", cut.len());
            }
        }
    }
}
