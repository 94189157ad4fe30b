//! A planned removal of one vertex (thesis §3.1.7, §4.4.1): the spoke flips and the weld
//! of its four-face cluster, what refinement needs to rebuild its ring, and the MAPS data
//! of the removal. Planned by `cluster`, guarded by `guard`, carried out on the rings here,
//! recorded by `record`; the parametrization (`param`) moves the vertices on its star.

use glam::{DVec2, DVec3};
use smallvec::SmallVec;

use super::conformal::Flattening;
use super::rings::{RingVec, Rings};

/// A planned removal of one vertex.
#[derive(Debug, Clone, PartialEq)]
pub struct ClusterPlan {
    /// The removed vertex.
    pub vertex: u32,
    /// Its 1-ring before the flips (the level's connectivity): cyclic, or open from one
    /// boundary neighbour to the other for a boundary vertex.
    pub ring: RingVec<u32>,
    /// Whether the vertex lies on a boundary: it is removed along it, by a weld that
    /// leaves one triangle (b0, r, b1) and makes b0–b1 a boundary edge.
    pub boundary: bool,
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
    /// For a vertex removed along a feature line: the line's two ends around it (joined by
    /// the diagonal) and the new feature edge's distance bound.
    pub along_line: Option<([u32; 2], f64)>,
    /// Whether a new triangle is below the angle floor (down to
    /// `cluster::NEARLY_FREE_FLOOR_DEGREES`); `error` then includes the premium.
    pub under_floor: bool,
}

impl ClusterPlan {
    /// The ring's conformal flattening (the vertex at the origin), as planning computed
    /// it: recomputed from the positions when needed, so a level's plans stay small while
    /// the recorder holds them.
    pub fn flattening(&self, positions: &[DVec3]) -> RingVec<DVec2> {
        let ring_points: RingVec<DVec3> = self.ring.iter().map(|&r| positions[r as usize]).collect();
        Flattening::of_star(positions[self.vertex as usize], &ring_points, self.boundary)
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

/// Whether `plan`, made on an earlier state of the rings, can still be carried out: the
/// vertex has the same ring, no flip or weld would create an edge that now exists (or join
/// two fenced vertices, [`Rings::fence`]), and no
/// ring vertex would drop below degree 3 (the topological conditions of [`super::cluster::plan_cluster`];
/// its geometric ones depend on positions only). Used when a level drops some of its plans
/// and replays the others.
pub fn plan_still_applies(plan: &ClusterPlan, rings: &Rings) -> bool {
    if rings.ring(plan.vertex) != plan.ring.as_slice() {
        return false;
    }
    let mut gain: RingVec<i64> = smallvec::smallvec![0; plan.ring.len()];
    let slot = |id: u32| plan.ring.iter().position(|&r| r == id).expect("a ring vertex");
    let drops_too_low = |id: u32, gain: &[i64]| !rings.may_lose_neighbour(id, gain[slot(id)]);
    let (ears, weld) = plan.triangles.split_at(plan.flips.len());
    for &[prev, apex, next] in ears {
        if !rings.may_join(prev, next) || drops_too_low(apex, &gain) {
            return false;
        }
        gain[slot(apex)] -= 1;
        gain[slot(prev)] += 1;
        gain[slot(next)] += 1;
    }
    if let [[c0, c1, c2]] = *weld {
        return rings.may_join(c0, c2) && !drops_too_low(c1, &gain);
    }
    let ([c0, c1, c2], [_, _, c3]) = (weld[0], weld[1]);
    rings.may_join(c0, c2) && !drops_too_low(c1, &gain) && !drops_too_low(c3, &gain)
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
    match plan.boundary {
        true => rings.weld_boundary(plan.vertex),
        false => rings.weld(plan.vertex, plan.weld_to),
    }
}
