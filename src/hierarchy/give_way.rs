//! What gives way to the user's vertex target (#34's decision: the target comes first).
//!
//! While a target is short, and each counted in [`TargetReport`]:
//! 0. before the first level, kept vertices beyond the target are released, weakest first
//!    (so many could never reach it); on every level, a kept or stranded vertex (a
//!    corner, a junction or end of lines, a boundary vertex where a line meets it) whose
//!    removal planned as if released costs at most the level's error limit
//!    divided by [`FEATURE_PREMIUM`] is released and ranked with the others
//!    ([`GiveWay::cheap_to_release`]): a feature gives way where keeping it would make the
//!    level remove dearer vertices instead. Keeping every feature until a level is stuck
//!    spent the budget on the rest of the surface: the helmet CAD part (genus 3) at 10 %
//!    had 7.45 % Hausdorff that way against meshoptimizer's 3.37 %, 3.58 % with this rule.
//!
//! When a level removes nothing:
//! 1. the smallest angle a cluster may make ([`super::cluster::ClusterRules::min_angle`],
//!    5°) is relaxed in steps down to 0.5° (a cluster may still go below the floor only
//!    where its star already had a smaller angle);
//! 2. kept feature and boundary vertices are released, weakest first by the feature
//!    strength the voting tensor measures (λ2 + λ3 of eq. 4.2, normalised: a weak corner
//!    of a rough scan before a CAD corner), in batches of the vertices still to remove,
//!    doubling; a released vertex on a line (two feature edges, or a boundary) is still
//!    removed only along it, and the floor returns to 5°;
//! 3. when no kept vertex is left, vertices of inside feature lines are let off their
//!    lines, weakest first, in the same batches;
//! 4. only when nothing is left to release, the floor goes on down to 0°.
//!
//! Step 4 comes after steps 2–3 where the decision's literal order would put the whole
//! floor first: below 0.5° a cluster makes needles (#34 targets a 0.5° minimum), and
//! releasing a weak feature costs less than a needle. What never gives way: genus,
//! manifoldness, no normal flip, the intersection guard, the exact round trip, boundary
//! loops never closed (a loop of three keeps its vertices), texture seams, the vertices
//! the user marked and, with `--feature-vertices keep`, the feature vertices.

use serde::Serialize;

use rayon::prelude::*;

use super::cluster::{ClusterRules, FEATURE_PREMIUM, LevelGeometry, plan_cluster_with};
use super::lines::FeatureLines;
use super::rings::Rings;

/// The angle floors (degrees) tried before any feature vertex is released.
pub(super) const FLOORS_BEFORE_RELEASE: [f64; 4] = [5.0, 2.0, 1.0, 0.5];

/// The angle floors (degrees) tried once every releasable vertex is released.
const FLOORS_AFTER_RELEASE: [f64; 2] = [0.25, 0.0];

/// How the build met its vertex target, and what gave way to meet it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TargetReport {
    /// The vertex target asked for (`None`: the build stopped at a level count or an
    /// error bound instead).
    pub target_vertices: Option<usize>,
    /// Whether the base domain has at most the target's vertices (or the target's
    /// topological floor, see `floor_vertices`).
    pub reached: bool,
    /// The fewest vertices the input's topology allows a base domain (4 per closed
    /// genus-0 component, the smallest triangulation of each higher genus, 3 per boundary
    /// loop of an open component).
    pub floor_vertices: usize,
    /// The smallest angle floor used, degrees (5 when it never gave way).
    pub min_angle_floor_deg: f64,
    /// Kept feature vertices (corners, junctions, line ends) released to reach the target.
    pub released_feature_vertices: usize,
    /// Kept boundary vertices (a boundary meeting a feature line) released.
    pub released_boundary_vertices: usize,
    /// Vertices of inside feature lines let off their lines (removed like surface
    /// vertices), once no kept vertex was left to release.
    pub released_line_vertices: usize,
    /// Clusters whose new triangles went below the angle floor (down to 0.5°) because
    /// they were nearly free (see `cluster::NEARLY_FREE_FLOOR_DEGREES`).
    pub clusters_under_floor: usize,
    /// When the target was not reached: what stopped the build.
    pub stopped_by: Option<String>,
}

impl TargetReport {
    /// What gave way, in words ("nothing" when nothing did).
    pub fn gave_way(&self) -> String {
        let mut parts = Vec::new();
        if self.min_angle_floor_deg < FLOORS_BEFORE_RELEASE[0] {
            parts.push(format!("angle floor relaxed to {}°", self.min_angle_floor_deg));
        }
        if self.clusters_under_floor > 0 {
            parts.push(format!(
                "{} nearly free clusters under the floor (≥ {}°)",
                self.clusters_under_floor,
                super::cluster::NEARLY_FREE_FLOOR_DEGREES
            ));
        }
        if self.released_feature_vertices > 0 {
            parts.push(format!("{} feature vertices released", self.released_feature_vertices));
        }
        if self.released_boundary_vertices > 0 {
            parts.push(format!("{} boundary vertices released", self.released_boundary_vertices));
        }
        if self.released_line_vertices > 0 {
            parts.push(format!("{} vertices let off their feature lines", self.released_line_vertices));
        }
        if parts.is_empty() { "nothing".to_string() } else { parts.join(", ") }
    }
}

/// The state of the give-way ladder during a build.
pub(super) struct GiveWay {
    /// Feature strength of every vertex (λ2 + λ3 of its normalised voting tensor).
    strength: Vec<f64>,
    /// Vertices never released: the user's marks and texture-seam vertices.
    fixed: Vec<bool>,
    /// Index into the floors: below `FLOORS_BEFORE_RELEASE.len()` before the release is
    /// exhausted, into `FLOORS_AFTER_RELEASE` after.
    floor_step: usize,
    /// Whether every releasable vertex has been released.
    exhausted: bool,
    /// Releases so far (the next batch doubles).
    rounds: u32,
    lowest_floor: f64,
    /// Clusters carried out below the floor (nearly free ones).
    pub(super) under_floor: usize,
    released_feature: usize,
    released_boundary: usize,
    released_line: usize,
}

/// One rung of the ladder.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Rung {
    /// The angle floor is now this many degrees.
    Floor(f64),
    /// This many vertices were released (the floor back to 5°).
    Released(usize),
}

impl GiveWay {
    pub(super) fn new(strength: Vec<f64>, fixed: Vec<bool>) -> Self {
        GiveWay {
            strength,
            fixed,
            floor_step: 0,
            exhausted: false,
            rounds: 0,
            lowest_floor: FLOORS_BEFORE_RELEASE[0],
            under_floor: 0,
            released_feature: 0,
            released_boundary: 0,
            released_line: 0,
        }
    }

    /// Whether `v` never gives way (a user mark, a texture seam, a kept feature).
    pub(super) fn is_fixed(&self, v: u32) -> bool {
        self.fixed[v as usize]
    }

    /// The current angle floor, degrees.
    pub(super) fn floor(&self) -> f64 {
        if self.exhausted { FLOORS_AFTER_RELEASE[self.floor_step] } else { FLOORS_BEFORE_RELEASE[self.floor_step] }
    }

    /// The next rung, with `need` vertices still to remove: the floor one step lower, or a
    /// batch of the weakest kept (or stranded line) vertices among `live` released from
    /// `kept` and `lines`; `None` when nothing is left to give.
    pub(super) fn next(
        &mut self,
        need: usize,
        live: &[u32],
        kept: &mut [bool],
        lines: &mut FeatureLines,
        rings: &Rings,
    ) -> Option<Rung> {
        if !self.exhausted {
            if self.floor_step + 1 < FLOORS_BEFORE_RELEASE.len() {
                self.floor_step += 1;
                return Some(self.lowered());
            }
            let mut released = self.release(need, live, kept, lines, rings, false);
            if released == 0 {
                released = self.release(need, live, kept, lines, rings, true);
            }
            if released > 0 {
                self.floor_step = 0;
                return Some(Rung::Released(released));
            }
            self.exhausted = true;
            self.floor_step = 0;
            return Some(self.lowered());
        }
        if self.floor_step + 1 < FLOORS_AFTER_RELEASE.len() {
            self.floor_step += 1;
            return Some(self.lowered());
        }
        None
    }

    /// Before the first level: releases the weakest kept vertices beyond the `target`
    /// (more kept vertices than the target allows could never reach it); returns how
    /// many.
    pub(super) fn release_to_budget(
        &mut self,
        target: usize,
        live: &[u32],
        kept: &mut [bool],
        lines: &mut FeatureLines,
        rings: &Rings,
    ) -> usize {
        let mut candidates: Vec<u32> =
            live.iter().copied().filter(|&v| !self.fixed[v as usize] && kept[v as usize]).collect();
        if candidates.len() <= target {
            return 0;
        }
        self.weakest_first(&mut candidates);
        let excess = candidates.len() - target;
        self.release_these(&candidates[..excess], kept, lines, rings);
        excess
    }

    /// The vertices a level may release because removing them costs little (step 0 of
    /// the ladder, every level while a target is short): kept or stranded vertices among
    /// `live` (not `waiting`) whose removal planned as if released
    /// ([`plan_cluster_with`]) costs at most `limit` / [`FEATURE_PREMIUM`], with that
    /// cost. A feature vertex so gives way only where keeping it would make the level
    /// remove a vertex dearer than it by the premium.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn cheap_to_release(
        &self,
        live: &[u32],
        waiting: &rustc_hash::FxHashSet<u32>,
        kept: &[bool],
        rings: &Rings,
        geometry: LevelGeometry<'_>,
        rules: &ClusterRules,
        limit: f64,
    ) -> Vec<(f64, u32)> {
        let lines = geometry.lines;
        let bar = limit / FEATURE_PREMIUM;
        live.par_iter()
            .copied()
            .filter(|&v| {
                !self.fixed[v as usize] && !waiting.contains(&v) && (kept[v as usize] || lines.is_stranded(v, rings))
            })
            .filter_map(|v| {
                plan_cluster_with(v, rings, geometry, rules, true).filter(|p| p.error <= bar).map(|p| (p.error, v))
            })
            .collect()
    }

    /// Releases `vertices` as [`GiveWay::cheap_to_release`] planned them: a boundary
    /// vertex to go along its boundary, any other off its lines. (Vertices inside lines
    /// are not released this way: letting them off when cheap broke fandisk's creases for
    /// no gain elsewhere — they go only when a level is stuck, step 3.)
    pub(super) fn release_planned(
        &mut self,
        vertices: &[(f64, u32)],
        kept: &mut [bool],
        lines: &mut FeatureLines,
        rings: &Rings,
    ) {
        for &(_, v) in vertices {
            let was_kept = std::mem::replace(&mut kept[v as usize], false);
            if rings.is_boundary(v) {
                lines.release(v, rings);
                self.released_boundary += 1;
            } else {
                lines.leave(v, rings);
                if was_kept {
                    self.released_feature += 1;
                } else {
                    self.released_line += 1;
                }
            }
        }
    }

    fn release_these(&mut self, vertices: &[u32], kept: &mut [bool], lines: &mut FeatureLines, rings: &Rings) {
        for &v in vertices {
            kept[v as usize] = false;
            lines.release(v, rings);
            if rings.is_boundary(v) {
                self.released_boundary += 1;
            } else {
                self.released_feature += 1;
            }
        }
    }

    /// Vertex `v`'s feature strength (0 when features are not asked for).
    pub(super) fn strength(&self, v: u32) -> f64 {
        self.strength.get(v as usize).copied().unwrap_or(0.0)
    }

    /// Sorts `vertices` weakest first by feature strength, ties by id.
    fn weakest_first(&self, vertices: &mut [u32]) {
        vertices.sort_by(|&a, &b| self.strength[a as usize].total_cmp(&self.strength[b as usize]).then(a.cmp(&b)));
    }

    fn lowered(&mut self) -> Rung {
        let floor = self.floor();
        self.lowest_floor = self.lowest_floor.min(floor);
        Rung::Floor(floor)
    }

    /// Releases the weakest `need · 2^rounds` (at least 16) releasable vertices: kept and
    /// stranded ones, or with `off_lines` the vertices on inside feature lines, which
    /// then leave their lines; returns how many.
    fn release(
        &mut self,
        need: usize,
        live: &[u32],
        kept: &mut [bool],
        lines: &mut FeatureLines,
        rings: &Rings,
        off_lines: bool,
    ) -> usize {
        let releasable = |v: u32| match off_lines {
            false => kept[v as usize] || lines.is_stranded(v, rings),
            true => lines.is_on_line(v) && !rings.is_boundary(v),
        };
        let mut candidates: Vec<u32> =
            live.iter().copied().filter(|&v| !self.fixed[v as usize] && releasable(v)).collect();
        self.weakest_first(&mut candidates);
        let batch = need.max(16).saturating_mul(1 << self.rounds.min(20));
        self.rounds += 1;
        candidates.truncate(batch);
        if off_lines {
            for &v in &candidates {
                lines.leave(v, rings);
            }
            self.released_line += candidates.len();
        } else {
            self.release_these(&candidates, kept, lines, rings);
        }
        candidates.len()
    }

    /// The report of a build that ended with `vertices` live vertices.
    pub(super) fn report(
        &self,
        target: Option<usize>,
        vertices: usize,
        floor_vertices: usize,
        stopped_by: Option<String>,
    ) -> TargetReport {
        let reached = target.is_none_or(|t| vertices <= t.max(floor_vertices));
        TargetReport {
            target_vertices: target,
            reached,
            floor_vertices,
            min_angle_floor_deg: self.lowest_floor,
            released_feature_vertices: self.released_feature,
            released_boundary_vertices: self.released_boundary,
            released_line_vertices: self.released_line,
            clusters_under_floor: self.under_floor,
            stopped_by: if reached { None } else { stopped_by },
        }
    }
}

/// The fewest vertices a surface of `triangles`' topology can keep, summed over its
/// components: a closed component of genus g needs the smallest triangulation of its
/// surface (4 for a sphere; Ringel & Youngs' ⌈(7 + √(1 + 48g)) / 2⌉ otherwise, 7 for a
/// torus), an open one 3 vertices per boundary loop (one triangle for a disc).
pub fn topological_floor(vertex_count: usize, triangles: &[[u32; 3]]) -> usize {
    let mut parent: Vec<u32> = (0..vertex_count as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            parent[v as usize] = parent[parent[v as usize] as usize];
            v = parent[v as usize];
        }
        v
    }
    for t in triangles {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[k]));
            if a != b {
                parent[a.max(b) as usize] = a.min(b);
            }
        }
    }
    let mut directed = rustc_hash::FxHashSet::default();
    for t in triangles {
        for k in 0..3 {
            directed.insert([t[k], t[(k + 1) % 3]]);
        }
    }
    // Per component: vertices, undirected edges, faces, boundary edges.
    let mut counts: rustc_hash::FxHashMap<u32, [i64; 4]> = rustc_hash::FxHashMap::default();
    let mut seen = vec![false; vertex_count];
    for t in triangles {
        let c = root(&mut parent, t[0]);
        let entry = counts.entry(c).or_default();
        entry[2] += 1;
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if !seen[a as usize] {
                seen[a as usize] = true;
                entry[0] += 1;
            }
            if !directed.contains(&[b, a]) {
                entry[1] += 1;
                entry[3] += 1;
            } else if a < b {
                entry[1] += 1;
            }
        }
    }
    let loops = boundary_loops_by_component(triangles, &directed, &mut parent);
    counts
        .iter()
        .map(|(c, &[v, e, f, _])| {
            let b = loops.get(c).copied().unwrap_or(0);
            if b > 0 {
                return (3 * b) as usize;
            }
            let genus = ((2 - (v - e + f)) / 2).max(0) as f64;
            if genus == 0.0 { 4 } else { ((7.0 + (1.0 + 48.0 * genus).sqrt()) / 2.0).ceil() as usize }
        })
        .sum()
}

/// Boundary loops per component root, followed along the open directed edges.
fn boundary_loops_by_component(
    triangles: &[[u32; 3]],
    directed: &rustc_hash::FxHashSet<[u32; 2]>,
    parent: &mut [u32],
) -> rustc_hash::FxHashMap<u32, i64> {
    let mut next: rustc_hash::FxHashMap<u32, Vec<u32>> = rustc_hash::FxHashMap::default();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if !directed.contains(&[b, a]) {
                next.entry(a).or_default().push(b);
            }
        }
    }
    let mut loops: rustc_hash::FxHashMap<u32, i64> = rustc_hash::FxHashMap::default();
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    for start in starts {
        if next.get(&start).is_none_or(Vec::is_empty) {
            continue;
        }
        let mut v = start;
        while let Some(w) = next.get_mut(&v).and_then(Vec::pop) {
            v = w;
            if v == start {
                break;
            }
        }
        let mut c = start;
        while parent[c as usize] != c {
            c = parent[c as usize];
        }
        *loops.entry(c).or_default() += 1;
    }
    loops
}
