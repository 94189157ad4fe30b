//! The record of a simplification: each level's plans written into the removals (each
//! removed vertex's point on the next coarser level, the edge to split, the link edges to
//! flip back), and, when the build checks itself against OpenMesh, carried out on the
//! OpenMesh store too (#20: the build plans on the Rust rings alone; refinement builds its
//! store from the base domain in one call). Planning needs only the rings, the quadrics and
//! the parametrization, so the record runs on its own thread, one level behind.

use std::time::Instant;

use glam::DVec3;

use super::param::ParamPoint;
use super::plan::ClusterPlan;
use super::store::expect_done;
use super::{LevelMesh, Removal};
use crate::error::Result;
use crate::ffi::{CollapseOptions, HalfEdgeMesh};

/// The store, the removals and the parametrization, level by level.
pub(super) struct Recorder<'a> {
    positions: &'a [DVec3],
    /// The half-edge store, at the last recorded level, when the build replays its plans
    /// on OpenMesh to check them.
    store: Option<HalfEdgeMesh>,
    /// Every removal so far, in order.
    removals: Vec<Removal>,
    /// The link edges of the removals (see [`Removal::restore`]).
    restore: Vec<[u32; 2]>,
    /// Where each step's removals start, plus the end.
    step_starts: Vec<usize>,
    /// Every level's mesh, when recorded.
    levels: Option<Vec<LevelMesh>>,
    /// Seconds spent on the store, the removal records and level exports.
    seconds: [f64; 3],
}

impl<'a> Recorder<'a> {
    /// Starts at the input (`triangles`, recorded as the first level if asked), replaying
    /// the plans on `store` when one is given.
    pub fn new(
        positions: &'a [DVec3],
        triangles: &[[u32; 3]],
        store: Option<HalfEdgeMesh>,
        record_levels: bool,
    ) -> Self {
        let levels = record_levels.then(|| vec![LevelMesh::compact(positions, triangles)]);
        Recorder {
            positions,
            store,
            removals: Vec::new(),
            restore: Vec::new(),
            step_starts: vec![0],
            levels,
            seconds: [0.0; 3],
        }
    }

    /// Records one simplification step: its plans and the level's faces after them (the
    /// planning rings', given when levels are recorded).
    ///
    /// # Errors
    /// [`crate::Error::Internal`] if OpenMesh refuses a planned operation.
    pub fn record(&mut self, plans: &[ClusterPlan], faces: Option<&[[u32; 3]]>) -> Result<()> {
        let clock = Instant::now();
        if let Some(store) = &mut self.store {
            apply_to_store(store, plans)?;
        }
        let stored = Instant::now();
        let step = (self.step_starts.len() - 1) as u32;
        for plan in plans {
            let point = ParamPoint { face: plan.triangles[plan.location.0], bary: plan.location.1 };
            let restore_start = self.restore.len() as u32;
            self.restore.extend(plan.triangles[..plan.flips.len()].iter().rev().map(|ear| [ear[0], ear[1]]));
            self.removals.push(Removal {
                vertex: plan.vertex,
                step,
                degree: plan.ring.len() as u32,
                boundary: plan.boundary,
                local: point,
                diagonal: plan.diagonal,
                restore: [restore_start, self.restore.len() as u32],
            });
        }
        self.step_starts.push(self.removals.len());
        let parametrized = Instant::now();
        if let (Some(levels), Some(faces)) = (&mut self.levels, faces) {
            levels.push(LevelMesh::compact(self.positions, faces));
        }
        self.seconds[0] += (stored - clock).as_secs_f64();
        self.seconds[1] += (parametrized - stored).as_secs_f64();
        self.seconds[2] += parametrized.elapsed().as_secs_f64();
        Ok(())
    }

    /// What was recorded, with the final base-domain point of every removed vertex.
    pub fn finish(self) -> Recorded {
        Recorded {
            store: self.store,
            removals: self.removals,
            restore: self.restore,
            step_starts: self.step_starts,
            levels: self.levels.unwrap_or_default(),
            seconds: self.seconds,
        }
    }
}

/// Replays the planned flips, then the welds, on the store (one call each; boundary welds,
/// of degree 3, in a call of their own).
fn apply_to_store(store: &mut HalfEdgeMesh, plans: &[ClusterPlan]) -> Result<()> {
    let flips: Vec<[u32; 2]> = plans.iter().flat_map(|p| p.flips.iter().map(move |&a| [p.vertex, a])).collect();
    expect_done("flip", &flips, &store.flip_edges(&flips)?)?;
    for (boundary, degree) in [(false, 4), (true, 3)] {
        let welds: Vec<[u32; 2]> =
            plans.iter().filter(|p| p.boundary == boundary).map(|p| [p.vertex, p.weld_to]).collect();
        if welds.is_empty() {
            continue;
        }
        let options = CollapseOptions { required_degree: degree, check_normals: false };
        expect_done("weld", &welds, &store.collapse_halfedges(&welds, options)?)?;
    }
    Ok(())
}

/// Everything a [`Recorder`] kept.
pub(super) struct Recorded {
    /// The store the plans were replayed on, when they were.
    pub store: Option<HalfEdgeMesh>,
    pub removals: Vec<Removal>,
    pub restore: Vec<[u32; 2]>,
    pub step_starts: Vec<usize>,
    pub levels: Vec<LevelMesh>,
    /// Store, removal-record and export seconds.
    pub seconds: [f64; 3],
}
