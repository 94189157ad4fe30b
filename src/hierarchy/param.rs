//! The hierarchical parametrization built during simplification (MAPS, Lee et al. 1998;
//! thesis §4.4.1.2): every removed vertex is a point (face, barycentric coordinates) on the
//! current coarse level, and when a face it lies on disappears its point is carried through
//! the conformal flattening of the removed vertex onto the face that replaces it.

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use serde::Serialize;

use super::conformal::locate;
use super::cost::point_triangle_distance_squared;
use super::face_key;
use super::plan::ClusterPlan;
use crate::mesh::UnitFrame;

/// A point on a level of the hierarchy: a face (counter-clockwise vertex ids) and
/// barycentric coordinates (non-negative, summing to one).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ParamPoint {
    /// The face's vertices.
    pub face: [u32; 3],
    /// Barycentric coordinates with respect to `face`.
    pub bary: [f64; 3],
}

/// Parameter points of the removed vertices, bucketed by the face they lie on: each
/// face's vertices form a list threaded through `next` (no allocation per face). Each
/// face also knows the [`WORST`] of its vertices farthest from it, which is what the
/// clusters' error measure reads (every vertex would cost each candidate cluster a
/// point location per level).
#[derive(Debug, Default)]
pub struct ParamBuckets {
    heads: FxHashMap<[u32; 3], Bucket>,
    next: Vec<u32>,
    points: Vec<Option<ParamPoint>>,
}

/// Where the vertices of a level and of its parametrized points are, in the unit frame:
/// the level's own vertices' positions, then (a continued build, #40) its seeded vertices',
/// found in the input as they are needed, so the planning holds no copy of the input's
/// positions.
#[derive(Debug, Clone, Copy)]
pub struct PointPositions<'a> {
    /// The positions of the ids below its length (every id of a build that continues
    /// nothing).
    pub own: &'a [DVec3],
    /// A continued build's other ids: each id's input vertex, the input's positions and
    /// its unit frame.
    pub seeded: Option<(&'a [u32], &'a [DVec3], UnitFrame)>,
}

impl PointPositions<'_> {
    /// The position of `w`.
    ///
    /// # Panics
    /// For an id neither the level's nor seeded (a planning invariant).
    #[inline]
    pub fn of(&self, w: u32) -> DVec3 {
        match self.own.get(w as usize) {
            Some(&p) => p,
            None => {
                let (to_input, input, frame) = self.seeded.expect("a parametrized vertex beyond the level's is seeded");
                frame.to_unit(input[to_input[w as usize] as usize])
            }
        }
    }
}

/// How many moved points [`ParamBuckets::apply_removals`] holds at once (a batch holds at
/// least one plan's, however many).
pub const REMAP_BATCH: usize = 1 << 16;

/// How many of a face's parametrized vertices, the farthest from it, are kept at hand.
pub const WORST: usize = 2;

/// One face's list, its length and its farthest vertices (squared distance, vertex; `END`
/// unused).
#[derive(Debug, Clone, Copy)]
struct Bucket {
    head: u32,
    len: u32,
    worst: [(f64, u32); WORST],
}

/// Ends a bucket's list.
const END: u32 = u32::MAX;

impl ParamBuckets {
    /// No vertex parametrized yet, room for `vertices`.
    pub fn new(vertices: usize) -> Self {
        ParamBuckets { heads: FxHashMap::default(), next: vec![END; vertices], points: vec![None; vertices] }
    }

    /// Puts `vertex` at `point`, `distance` (squared) from the point's face.
    fn insert(&mut self, vertex: u32, point: ParamPoint, distance: f64) {
        let bucket = self.heads.entry(face_key(point.face)).or_insert(Bucket {
            head: END,
            len: 0,
            worst: [(f64::NEG_INFINITY, END); WORST],
        });
        self.next[vertex as usize] = bucket.head;
        bucket.head = vertex;
        bucket.len += 1;
        if let Some(slot) = (0..WORST).min_by(|&a, &b| bucket.worst[a].0.total_cmp(&bucket.worst[b].0))
            && distance > bucket.worst[slot].0
        {
            bucket.worst[slot] = (distance, vertex);
        }
        self.points[vertex as usize] = Some(point);
    }

    /// Each vertex with a point in `seeds` (one entry per vertex) put there, in the order
    /// `order` gives them (which decides between points equally far from their face, as
    /// insertion order does in every bucket): a hierarchy continued from removals made
    /// before (a partitioned build's parts, #40). The seeds become the points, so they are
    /// not held twice.
    pub fn seeded(seeds: Vec<Option<ParamPoint>>, positions: PointPositions, order: impl Iterator<Item = u32>) -> Self {
        let mut buckets = ParamBuckets { heads: FxHashMap::default(), next: vec![END; seeds.len()], points: seeds };
        for v in order {
            if let Some(point) = buckets.points[v as usize] {
                buckets.insert(v, point, distance_to(positions, v, point.face));
            }
        }
        buckets
    }

    /// Calls `f` with the vertices parametrized onto `face` (any rotation) that lie farthest
    /// from it (at most [`WORST`]) and their points.
    pub fn for_each_farthest_on(&self, face: [u32; 3], mut f: impl FnMut(u32, &ParamPoint)) {
        let Some(bucket) = self.heads.get(&face_key(face)) else { return };
        for &(_, w) in &bucket.worst {
            if let Some(Some(point)) = self.points.get(w as usize) {
                f(w, point);
            }
        }
    }

    /// Applies one level's removals (the three categories of Lee et al.): the vertices on
    /// each removed vertex's star faces are re-mapped through its flattening onto the
    /// retriangulated ring, and the removed vertex is placed where its image (the origin)
    /// falls.
    ///
    /// The removed vertices are independent (no two share a face, and a plan's new
    /// triangles hold only its ring vertices), so no plan's star faces hold another's
    /// re-mapped points: the moves of a batch of plans (about [`REMAP_BATCH`] points) are
    /// computed in parallel from the buckets as they were, then carried out in plan order,
    /// exactly as one removal after the other. Batches bound the moves held at once: a
    /// partitioned build's continuation (#40) starts with every vertex its parts removed
    /// on its few faces, and one level moves most of them.
    pub fn apply_removals(&mut self, plans: &[ClusterPlan], positions: PointPositions) {
        let mut rest = plans;
        while !rest.is_empty() {
            let (batch, after) = rest.split_at(self.batch_length(rest));
            rest = after;
            let moves: Vec<Vec<(u32, ParamPoint, f64)>> =
                batch.par_iter().map(|plan| self.removal_moves(plan, positions)).collect();
            for (plan, moves) in batch.iter().zip(moves) {
                for face in star_faces(plan) {
                    self.heads.remove(&face_key(face));
                }
                for (w, point, distance) in moves {
                    self.insert(w, point, distance);
                }
            }
        }
    }

    /// How many of `plans`, from the first, move about [`REMAP_BATCH`] points (at least
    /// one plan).
    fn batch_length(&self, plans: &[ClusterPlan]) -> usize {
        let mut moved = 0;
        for (k, plan) in plans.iter().enumerate() {
            let on_star: usize =
                star_faces(plan).filter_map(|f| self.heads.get(&face_key(f))).map(|b| b.len as usize).sum();
            moved += on_star + 1;
            if moved > REMAP_BATCH && k > 0 {
                return k;
            }
        }
        plans.len()
    }

    /// Where one removal sends the vertices on its star faces, in bucket order, and the
    /// removed vertex itself (last), each with its squared distance from its new face.
    fn removal_moves(&self, plan: &ClusterPlan, positions: PointPositions) -> Vec<(u32, ParamPoint, f64)> {
        let flat = plan.flattening(positions.own);
        let flat_triangles = plan.flat_triangles(&flat);
        let mut moves = Vec::new();
        for star_face in star_faces(plan) {
            let Some(&Bucket { head: mut w, .. }) = self.heads.get(&face_key(star_face)) else { continue };
            while w != END {
                if let Some(old) = self.points[w as usize] {
                    let image = old
                        .face
                        .iter()
                        .zip(old.bary)
                        .fold(DVec2::ZERO, |acc, (&id, b)| acc + plan.image(id, &flat) * b);
                    let (t, bary) = locate(image, &flat_triangles);
                    let face = plan.triangles[t];
                    moves.push((w, ParamPoint { face, bary }, distance_to(positions, w, face)));
                }
                w = self.next[w as usize];
            }
        }
        let own = ParamPoint { face: plan.triangles[plan.location.0], bary: plan.location.1 };
        moves.push((plan.vertex, own, distance_to(positions, plan.vertex, own.face)));
        moves
    }

    /// The final points: `None` for vertices never removed.
    pub fn into_points(self) -> Vec<Option<ParamPoint>> {
        self.points
    }
}

/// The faces around a removed vertex before its removal.
fn star_faces(plan: &ClusterPlan) -> impl Iterator<Item = [u32; 3]> + '_ {
    let d = plan.ring.len();
    (0..if plan.boundary { d - 1 } else { d }).map(move |k| [plan.vertex, plan.ring[k], plan.ring[(k + 1) % d]])
}

/// Squared distance from vertex `w` to the triangle `face`.
fn distance_to(positions: PointPositions, w: u32, face: [u32; 3]) -> f64 {
    let [a, b, c] = face.map(|v| positions.own[v as usize]);
    point_triangle_distance_squared(positions.of(w), a, b, c)
}
