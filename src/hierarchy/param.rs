//! The hierarchical parametrization built during simplification (MAPS, Lee et al. 1998;
//! thesis §4.4.1.2): every removed vertex is a point (face, barycentric coordinates) on the
//! current coarse level, and when a face it lies on disappears its point is carried through
//! the conformal flattening of the removed vertex onto the face that replaces it.

use glam::{DVec2, DVec3};
use rustc_hash::FxHashMap;
use serde::Serialize;

use super::cluster::ClusterPlan;
use super::conformal::locate;
use super::face_key;

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
/// face's vertices form a list threaded through `next` (no allocation per face).
#[derive(Debug, Default)]
pub struct ParamBuckets {
    heads: FxHashMap<[u32; 3], u32>,
    next: Vec<u32>,
    points: Vec<Option<ParamPoint>>,
}

/// Ends a bucket's list.
const END: u32 = u32::MAX;

impl ParamBuckets {
    /// No vertex parametrized yet, room for `vertices`.
    pub fn new(vertices: usize) -> Self {
        ParamBuckets { heads: FxHashMap::default(), next: vec![END; vertices], points: vec![None; vertices] }
    }

    fn insert(&mut self, vertex: u32, point: ParamPoint) {
        let head = self.heads.entry(face_key(point.face)).or_insert(END);
        self.next[vertex as usize] = *head;
        *head = vertex;
        self.points[vertex as usize] = Some(point);
    }

    /// Calls `f` with each vertex parametrized onto `face` (any rotation) and its point.
    pub fn for_each_on(&self, face: [u32; 3], mut f: impl FnMut(u32, &ParamPoint)) {
        let Some(&head) = self.heads.get(&face_key(face)) else { return };
        let mut w = head;
        while w != END {
            if let Some(point) = &self.points[w as usize] {
                f(w, point);
            }
            w = self.next[w as usize];
        }
    }

    /// Applies one removal (the three categories of Lee et al.): the vertices on the
    /// removed vertex's star faces are re-mapped through its flattening onto the
    /// retriangulated ring, and the removed vertex is placed where its image (the origin)
    /// falls. Returns the removed vertex's own point.
    pub fn apply_removal(&mut self, plan: &ClusterPlan, positions: &[DVec3]) -> ParamPoint {
        let v = plan.vertex;
        let d = plan.ring.len();
        let flat = plan.flattening(positions);
        let flat_triangles = plan.flat_triangles(&flat);
        for k in 0..d {
            let star_face = [v, plan.ring[k], plan.ring[(k + 1) % d]];
            let Some(mut w) = self.heads.remove(&face_key(star_face)) else { continue };
            while w != END {
                let after = self.next[w as usize];
                if let Some(old) = self.points[w as usize] {
                    let image = old
                        .face
                        .iter()
                        .zip(old.bary)
                        .fold(DVec2::ZERO, |acc, (&id, b)| acc + plan.image(id, &flat) * b);
                    let (t, bary) = locate(image, &flat_triangles);
                    self.insert(w, ParamPoint { face: plan.triangles[t], bary });
                }
                w = after;
            }
        }
        let own = ParamPoint { face: plan.triangles[plan.location.0], bary: plan.location.1 };
        self.insert(v, own);
        own
    }

    /// The final points: `None` for vertices never removed.
    pub fn into_points(self) -> Vec<Option<ParamPoint>> {
        self.points
    }
}
