//! Each vertex's cluster plan kept from one level to the next while nothing it reads has
//! changed (#35: a level that removes a handful of vertices — an assembly creeping past
//! the intersection guard, the last levels of any build, a level tried again without its
//! offenders — no longer plans every vertex of the mesh again).
//!
//! A plan ([`super::cluster::plan_cluster`]) of a vertex `v` reads `v`'s ring, the rings of
//! its ring's vertices (`Rings::may_join`'s edges and copies' edges, their degrees), the
//! positions (never moved), `v`'s quadric, the parameter points on `v`'s star faces, the
//! feature-line edges at `v`, and the level's rules. A level's removal changes the rings
//! of its own ring's vertices only; the quadrics it shares go to its diagonal's ends, its
//! parameter points onto its new faces and its merged line edge between ring vertices —
//! all vertices of its ring. So after a level, the plans of those vertices and of their
//! neighbours are stale ([`PlanCache::forget_around`]) and every other plan is the one
//! planning it again would make, bit for bit: the build's output does not change (checked
//! in debug builds by planning a sample of the reused vertices again). A change of the
//! rules or a release by the give-way ladder forgets every plan.

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
}

impl PlanCache {
    /// Nothing planned yet for `slots` vertices.
    pub(super) fn new(slots: usize) -> Self {
        PlanCache { entries: (0..slots).map(|_| Entry::Stale).collect(), rules: None }
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

    /// Records `v`'s fresh plan (or that it has none), keeping the plan itself if its error
    /// is within `bound`.
    pub(super) fn store(&mut self, v: u32, plan: Option<ClusterPlan>, bound: f64) {
        self.entries[v as usize] = match plan {
            None => Entry::Invalid,
            Some(plan) => Entry::Planned { error: plan.error, plan: (plan.error <= bound).then(|| Box::new(plan)) },
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
