//! The sliver budget of the clusters that go under the angle floor (#34).
//!
//! A cluster whose new triangles go below the 5° floor (down to
//! [`super::cluster::NEARLY_FREE_FLOOR_DEGREES`]) because it is nearly free is taken only
//! while the level's share of slivers — triangles with an angle under 5°, as `compare`
//! counts them — stays within the input's. A CAD output that is mostly
//! slivers so gets the clusters its flat faces need; a clean mesh gets none that would make
//! it worse than it came.

use glam::DVec3;
use rayon::prelude::*;

use super::cost::min_angle_sine;
use super::plan::ClusterPlan;

/// The smallest angle of a triangle that is not a sliver, degrees (`compare`'s 5°).
const SLIVER_DEGREES: f64 = 5.0;

/// Live faces and slivers of the current level, and the input's sliver share.
#[derive(Debug, Clone)]
pub(super) struct SliverBudget {
    faces: usize,
    slivers: usize,
    share: f64,
}

fn is_sliver(a: DVec3, b: DVec3, c: DVec3) -> bool {
    min_angle_sine(a, b, c) < SLIVER_DEGREES.to_radians().sin()
}

impl SliverBudget {
    /// The budget of a build of `triangles` over `positions`.
    pub(super) fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> Self {
        let faces = triangles.len();
        let slivers = triangles
            .iter()
            .filter(|t| is_sliver(positions[t[0] as usize], positions[t[1] as usize], positions[t[2] as usize]))
            .count();
        let share = if faces == 0 { 0.0 } else { slivers as f64 / faces as f64 };
        SliverBudget { faces, slivers, share }
    }

    /// The change in faces and slivers `plan` makes.
    fn change(plan: &ClusterPlan, positions: &[DVec3]) -> (usize, isize) {
        let p = |v: u32| positions[v as usize];
        let d = plan.ring.len();
        let star = if plan.boundary { d - 1 } else { d };
        let removed =
            (0..star).filter(|&k| is_sliver(p(plan.vertex), p(plan.ring[k]), p(plan.ring[(k + 1) % d]))).count();
        let made = plan.triangles.iter().filter(|t| is_sliver(p(t[0]), p(t[1]), p(t[2]))).count();
        (star - plan.triangles.len(), made as isize - removed as isize)
    }

    /// Whether a cluster under the floor that makes one sliver more would fit.
    pub(super) fn has_room(&self) -> bool {
        (self.slivers + 1) as f64 <= self.allowed(self.faces)
    }

    /// The slivers allowed among `faces` live faces.
    fn allowed(&self, faces: usize) -> f64 {
        self.share * faces as f64
    }

    /// Counts `plan` as carried out if it may be: any plan at the floor; one under it only
    /// while the slivers stay within the input's share. Whether it was.
    pub(super) fn take(&mut self, plan: &ClusterPlan, positions: &[DVec3]) -> bool {
        let (lost, more) = Self::change(plan, positions);
        if plan.under_floor && (self.slivers as isize + more) as f64 > self.allowed(self.faces - lost) {
            return false;
        }
        self.count(lost, more);
        true
    }

    /// Counts a level's `plans` as carried out (their changes measured in parallel).
    pub(super) fn apply(&mut self, plans: &[ClusterPlan], positions: &[DVec3]) {
        let (lost, more) =
            plans.par_iter().map(|plan| Self::change(plan, positions)).reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
        self.count(lost, more);
    }

    fn count(&mut self, lost: usize, more: isize) {
        self.faces -= lost;
        self.slivers = (self.slivers as isize + more).max(0) as usize;
    }
}
