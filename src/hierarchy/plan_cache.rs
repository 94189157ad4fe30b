//! Each vertex's cluster plan kept from one level to the next while nothing it reads has
//! changed (#35: a level that removes a handful of vertices — an assembly creeping past
//! the intersection guard, the last levels of any build, a level tried again without its
//! offenders — no longer plans every vertex of the mesh again).
//!
//! A plan ([`super::cluster::plan_cluster`]) of a vertex `v` reads `v`'s ring, the rings of
//! its ring's vertices (`Rings::may_join`'s edges and copies' edges, their degrees), the
//! positions (never moved), `v`'s quadric, the parameter points on `v`'s star faces, the
//! feature-line edges at `v`, and the level's rules. A level's removal of `u` edits the rings
//! of `u`'s ring only; the quadrics it shares go to its diagonal's ends, its parameter points
//! onto its new faces and its merged line edge between ring vertices — all vertices of its
//! ring. So after a level ([`PlanCache::forget_after_level`]) the plans of the removed
//! vertices' rings are stale. A vertex `w` beside such a ring keeps its own ring, star,
//! quadric and lines; of its ring's rings a plan reads only two things:
//! - whether two of its ring vertices are joined (`may_join`): a removal deletes only edges
//!   at the removed vertex, so the answers change only where the level made an edge (a flip's
//!   or the weld's diagonal) between two of `w`'s ring vertices;
//! - whether a ring vertex may lose a neighbour after the plan's earlier flips gave it
//!   `gain ≥ 0` (`may_lose_neighbour`): always yes while its degree is above the fan's least,
//!   so the answers change only where a ring vertex's degree is, or was when `w` was
//!   planned, at that least.
//!
//! Every other plan is the one planning it again would make, bit for bit: the build's
//! output does not change (checked in debug builds by planning the reused vertices again,
//! a sample of them on large meshes). A change of the rules, or a release by the give-way
//! ladder, forgets every plan, a cheap release those around the released vertices; a build
//! whose rings hold copies of one vertex (a part of a partitioned build pinched at a border
//! vertex: `Rings::twin`), whose `may_join` reads the copies' edges too, forgets the
//! removed vertices' 2-rings.

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use super::cluster::ClusterRules;
use super::plan::ClusterPlan;
use super::rings::Rings;
use super::simplify::Candidate;

/// What is known of one vertex's cluster on the current level.
#[derive(Debug, Default)]
enum Entry {
    /// Not planned since something it reads changed.
    #[default]
    Stale,
    /// No valid cluster.
    Invalid,
    /// E(v) of its cluster, and the plan itself while ranking keeps it.
    Planned { error: f64, plan: Option<Box<ClusterPlan>> },
}

/// Plans kept across levels, by vertex.
#[derive(Debug)]
pub(super) struct PlanCache {
    entries: Vec<Entry>,
    /// The rules the entries were planned under.
    rules: Option<ClusterRules>,
    /// Whether every ring vertex of the vertex had a degree above the fan's least when it
    /// was planned (its plan's `may_lose_neighbour` checks then all said yes).
    roomy: Vec<bool>,
}

impl PlanCache {
    /// Nothing planned yet for `slots` vertices.
    pub(super) fn new(slots: usize) -> Self {
        PlanCache { entries: (0..slots).map(|_| Entry::Stale).collect(), rules: None, roomy: vec![false; slots] }
    }

    /// Forgets every plan if `rules` are not those the plans were made under.
    pub(super) fn use_rules(&mut self, rules: &ClusterRules) {
        if self.rules.as_ref() != Some(rules) {
            self.forget_all();
            self.rules = Some(*rules);
        }
    }

    /// Forgets every plan (the feature lines or the kept vertices changed).
    pub(super) fn forget_all(&mut self) {
        self.entries.par_iter_mut().for_each(|e| *e = Entry::Stale);
    }

    /// Forgets the plans of `vertices` and of their neighbours on `rings`: what a change of
    /// the vertices' rings, lines, quadrics or parameter points makes stale.
    pub(super) fn forget_around(&mut self, vertices: impl IntoIterator<Item = u32>, rings: &Rings) {
        for v in vertices {
            self.entries[v as usize] = Entry::Stale;
            for &r in rings.ring(v) {
                self.entries[r as usize] = Entry::Stale;
            }
        }
    }

    /// Forgets the plans a level's removals (`plans`, carried out on `rings`) made stale: the
    /// removed vertices' and their rings' and, beside those rings, the vertices between two
    /// of whose ring vertices the level made an edge, or a ring vertex of which is at (or
    /// was planned at) the least degree of a fan (see the module's documentation).
    pub(super) fn forget_after_level(&mut self, plans: &[ClusterPlan], rings: &Rings) {
        if rings.has_copies() {
            self.forget_around(plans.iter().flat_map(|p| p.ring.iter().copied().chain([p.vertex])), rings);
            return;
        }
        // Only the rings' vertices changed degree: a vertex beside one at the least, or
        // planned beside one, is stale. Marked in parallel, then forgotten in one pass.
        let roomy = &self.roomy;
        let stale: Vec<AtomicBool> = (0..self.entries.len()).map(|_| AtomicBool::new(false)).collect();
        let mark = |v: u32| stale[v as usize].store(true, Ordering::Relaxed);
        plans.par_iter().for_each(|plan| {
            mark(plan.vertex);
            for &r in &plan.ring {
                mark(r);
                let tight = !rings.may_lose_neighbour(r, 0);
                rings.ring(r).iter().filter(|&&w| tight || !roomy[w as usize]).for_each(|&w| mark(w));
            }
            for [a, b] in new_edges(plan) {
                rings.ring(a).iter().filter(|&&w| rings.has_edge(w, b)).for_each(|&w| mark(w));
            }
        });
        self.entries
            .par_iter_mut()
            .zip(stale.par_iter())
            .filter(|(_, s)| s.load(Ordering::Relaxed))
            .for_each(|(e, _)| *e = Entry::Stale);
    }

    /// Whether `v` must be planned again.
    pub(super) fn is_stale(&self, v: u32) -> bool {
        matches!(self.entries[v as usize], Entry::Stale)
    }

    /// E(v) as last planned (`None`: no valid cluster), unless stale.
    pub(super) fn error(&self, v: u32) -> Option<Option<f64>> {
        match &self.entries[v as usize] {
            Entry::Stale => None,
            Entry::Invalid => Some(None),
            Entry::Planned { error, .. } => Some(Some(*error)),
        }
    }

    /// The plan kept for `v`, if it is kept whole (within the bound it was stored under).
    #[cfg(debug_assertions)]
    pub(super) fn plan(&self, v: u32) -> Option<&ClusterPlan> {
        match &self.entries[v as usize] {
            Entry::Planned { plan: Some(plan), .. } => Some(plan),
            _ => None,
        }
    }

    /// Records `v`'s fresh plan (or that it has none) as [`kept_within`] made it; `roomy`:
    /// [`ring_is_roomy`] on the rings it was planned on.
    pub(super) fn store(&mut self, v: u32, planned: Planned, roomy: bool) {
        self.roomy[v as usize] = roomy;
        self.entries[v as usize] = match planned {
            None => Entry::Invalid,
            Some((error, plan)) => Entry::Planned { error, plan },
        };
    }

    /// `v` as a candidate of this level: its error and, if within `bound`, its plan (lent to
    /// the level and given back by [`PlanCache::give_back`]); `None` without a valid
    /// cluster. A plan above `bound` is dropped, to keep memory to what selection may take.
    pub(super) fn candidate(&mut self, v: u32, bound: f64) -> Option<Candidate> {
        match &mut self.entries[v as usize] {
            Entry::Stale => panic!("vertex {v} ranked without a plan"),
            Entry::Invalid => None,
            Entry::Planned { error, plan } => {
                let plan = plan.take().filter(|_| *error <= bound);
                Some(Candidate { error: *error, vertex: v, plan })
            }
        }
    }

    /// Takes back the plans the level did not use, where nothing has made them stale.
    pub(super) fn give_back(&mut self, ranked: Vec<Candidate>) {
        for candidate in ranked {
            if let (Some(plan), Entry::Planned { plan: slot @ None, error }) =
                (candidate.plan, &mut self.entries[candidate.vertex as usize])
                && plan.error == *error
            {
                *slot = Some(plan);
            }
        }
    }
}

/// A fresh plan as the cache stores it: `None` without a valid cluster, else E(v) and the
/// plan itself if it is within the bound ([`kept_within`]).
pub(super) type Planned = Option<(f64, Option<Box<ClusterPlan>>)>;

/// `plan` as the cache stores it, kept whole if its error is within `bound` (boxed where it
/// was made: ranking makes plans in parallel and stores them in one pass).
pub(super) fn kept_within(plan: Option<ClusterPlan>, bound: f64) -> Planned {
    plan.map(|plan| (plan.error, (plan.error <= bound).then(|| Box::new(plan))))
}

/// Whether every ring vertex of `v` has a degree above the least of a fan, so that any
/// plan's `may_lose_neighbour` checks on them say yes.
pub(super) fn ring_is_roomy(v: u32, rings: &Rings) -> bool {
    rings.ring(v).iter().all(|&r| rings.may_lose_neighbour(r, 0))
}

/// The edges a removal makes: each flip's (the cut ear's outer corners) and the weld's
/// diagonal.
fn new_edges(plan: &ClusterPlan) -> impl Iterator<Item = [u32; 2]> + '_ {
    plan.triangles[..plan.flips.len()].iter().map(|t| [t[0], t[2]]).chain([plan.diagonal])
}
