//! The intersection guard of simplification: a level's planned retriangulations must not
//! cut the surface they join (checked with CGAL's exact predicates through
//! [`super::added_triangle_intersections`]); the plans that would are left for a later level.

use rustc_hash::{FxHashMap, FxHashSet};

use super::crossings::KnownCrossings;
use super::face_key;
use super::intersections::{AddedPairs, AddedRuns, listed_pairs_intersect, triangle_intersections_across};
use super::plan::{ClusterPlan, apply_plan, plan_still_applies};
use super::rings::Rings;
use crate::error::Result;

/// The intersection guard: leaves out the plans whose new triangles would intersect the
/// level's surface as planned (CGAL's exact predicates; intersections already in the level
/// are not counted, nor a planned triangle's crossing of a face that the faces it replaces
/// already crossed: see [`crossings_before`]). The offending plans are dropped and the
/// others replayed on the rings in their order, dropping those that no longer apply without
/// the dropped ones ([`plan_still_applies`]); the faces that come back are then checked
/// against the planned triangles still kept, until nothing offends. Plans are never
/// re-planned, so each round after the first checks only the restored faces. Returns the
/// plans kept and the vertices whose plans offended. `known` lists the level's crossings
/// once that pays, and learns the new ones the rounds find.
pub(super) fn guard_plans(
    positions: &[glam::DVec3],
    level_faces: &[[u32; 3]],
    mut plans: Vec<ClusterPlan>,
    rings: &mut Rings,
    known: &mut KnownCrossings,
) -> Result<(Vec<ClusterPlan>, FxHashSet<u32>)> {
    known.list_when_it_pays(positions, level_faces)?;
    let mut restored = None;
    let mut offenders = FxHashSet::default();
    let mut found = Vec::new();
    loop {
        let offending = intersecting_plans(positions, level_faces, &plans, restored.as_ref(), known, &mut found)?;
        if offending.is_empty() {
            // The level's new crossings: those of the planned triangles kept (found only
            // once the crossings are listed).
            if !found.is_empty() {
                let kept: FxHashSet<u32> = plans.iter().map(|p| p.vertex).collect();
                for (faces, owners) in found {
                    if owners.iter().flatten().all(|v| kept.contains(v)) {
                        known.add(faces[0], faces[1]);
                    }
                }
            }
            return Ok((plans, offenders));
        }
        offenders.extend(&offending);
        rings.rollback();
        let mut dropped = FxHashSet::default();
        let mut kept = Vec::with_capacity(plans.len());
        for plan in plans {
            if offending.contains(&plan.vertex) || !plan_still_applies(&plan, rings) {
                dropped.insert(plan.vertex);
                continue;
            }
            apply_plan(&plan, rings)?;
            kept.push(plan);
        }
        plans = kept;
        restored = Some(dropped);
    }
}

/// The planned vertices whose new triangles intersect the surface.
///
/// The first round checks the planned triangles against each other and against the
/// level's faces they do not replace. A later round (`restored`: the vertices of plans just
/// dropped) checks only the faces that come back (the level's faces around those vertices)
/// against the planned triangles still kept: every other pair was checked by an earlier
/// round, and two faces of the level before can only cross where the level crossed
/// already, which is never counted. On an assembly whose parts interpenetrate, such pairs
/// are most of what a later round would find (samurai-monastery, #35).
fn intersecting_plans(
    positions: &[glam::DVec3],
    level_faces: &[[u32; 3]],
    plans: &[ClusterPlan],
    restored: Option<&FxHashSet<u32>>,
    known: &mut KnownCrossings,
    found: &mut Vec<FoundCrossing>,
) -> Result<FxHashSet<u32>> {
    // Each vertex's role in this round, looked up by the passes over the level's faces.
    let mut role = vec![0u8; positions.len()];
    for plan in plans {
        role[plan.vertex as usize] |= PLANNED;
    }
    for &v in restored.into_iter().flatten() {
        role[v as usize] |= RESTORED;
    }
    let has =
        |t: &[u32; 3], bit: u8, role: &[u8]| t.iter().any(|&v| role.get(v as usize).is_some_and(|r| r & bit != 0));
    let mut level_side = Vec::new();
    for t in level_faces {
        if !has(t, PLANNED, &role) && (restored.is_none() || has(t, RESTORED, &role)) {
            level_side.push(*t);
        }
    }
    // `owners` names each planned triangle's plan.
    let mut planned_side = Vec::new();
    let mut owners = Vec::new();
    // Each plan's triangle count: the first round's runs (later rounds take them one by one).
    let first_round = restored.is_none();
    let mut runs = Vec::with_capacity(if first_round { plans.len() } else { 0 });
    for plan in plans {
        planned_side.extend(&plan.triangles);
        owners.extend(std::iter::repeat_n(plan.vertex, plan.triangles.len()));
        if first_round {
            runs.push(plan.triangles.len());
        }
    }
    // Pairs index `kept` then `added`: the planned triangles are added in the first round
    // (tested among themselves too), kept in the later ones.
    // The first round boxes each plan's triangles together in the broad phase.
    let (kept, added, among_added, first_planned, runs) = match restored {
        None => (&level_side, &planned_side, AddedPairs::Tested, level_side.len(), AddedRuns::Sizes(&runs)),
        Some(_) => (&planned_side, &level_side, AddedPairs::LeftOut, 0, AddedRuns::Single),
    };
    let owner = |t: u32| (t as usize).checked_sub(first_planned).and_then(|i| owners.get(i).copied());
    let pairs = triangle_intersections_across(positions, kept, added, among_added, runs)?;
    if pairs.is_empty() {
        return Ok(FxHashSet::default());
    }
    // A pair's face by its index in the pairs' numbering (`kept` then `added`), read in
    // place: a joined copy would hold the level's faces a third time at the guard's peak.
    let combined = |t: u32| kept.get(t as usize).copied().unwrap_or_else(|| added[t as usize - kept.len()]);
    let stars: FxHashMap<u32, Vec<[u32; 3]>> = {
        let offending: FxHashSet<u32> = pairs.iter().flatten().filter_map(|&t| owner(t)).collect();
        let mut stars: FxHashMap<u32, Vec<[u32; 3]>> = offending.iter().map(|&v| (v, Vec::new())).collect();
        for &v in &offending {
            role[v as usize] |= OFFENDING;
        }
        for t in level_faces.iter().filter(|t| has(t, OFFENDING, &role)) {
            for v in t {
                if let Some(star) = stars.get_mut(v) {
                    star.push(*t);
                }
            }
        }
        stars
    };
    // What each face of a pair stands for in the level before: a planned triangle for its
    // plan's star, any other face for itself.
    let side = |t: u32| owner(t).map_or(Side::Face(t), Side::Plan);
    let region = |side: Side| -> Vec<[u32; 3]> {
        match side {
            Side::Plan(v) => stars[&v].clone(),
            Side::Face(t) => vec![combined(t)],
        }
    };
    let sides: Vec<[Side; 2]> = pairs.iter().map(|&[a, b]| [side(a), side(b)]).collect();
    let before = crossings_before(positions, &sides, &region, known)?;
    if known.listed() {
        found.extend(pairs.iter().map(|&[a, b]| ([combined(a), combined(b)], [owner(a), owner(b)])));
    }
    let mut offending = FxHashSet::default();
    for (k, pair) in pairs.iter().enumerate() {
        if !before[k] {
            offending.extend(pair.iter().filter_map(|&t| owner(t)));
        }
    }
    Ok(offending)
}

/// A vertex's roles in a guard round: its plan is in the round, its faces come back, its
/// plan offends.
const PLANNED: u8 = 1;
const RESTORED: u8 = 2;
const OFFENDING: u8 = 4;

/// An intersecting pair of faces a round found, with the plans whose triangles they are.
type FoundCrossing = ([[u32; 3]; 2], [Option<u32>; 2]);

/// What a face of an intersecting pair stands for in the level before the plans.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Side {
    /// A planned triangle: its plan's star (the plan's vertex).
    Plan(u32),
    /// Any other face: itself (its index in the pairs' numbering).
    Face(u32),
}

/// For each intersecting pair of a level as planned (as the [`Side`]s its faces stand
/// for), whether the surface already crossed itself there: whether a face of one side's
/// `region` (the faces it replaces, or itself) intersects a face of the other's in the level
/// before the plans. Inputs whose parts interpenetrate or touch (assemblies, scans with
/// overlapping sheets) keep those crossings at every level; the guard refuses only
/// crossings the plans would make (#34). Each distinct pair of sides is looked at once:
/// in the `known` crossings once they are listed, else by testing each pair of their faces
/// once.
fn crossings_before(
    positions: &[glam::DVec3],
    pairs: &[[Side; 2]],
    region: &dyn Fn(Side) -> Vec<[u32; 3]>,
    known: &mut KnownCrossings,
) -> Result<Vec<bool>> {
    let mut distinct = pairs.to_vec();
    distinct.sort_unstable();
    distinct.dedup();
    let crossed = match known.listed() {
        true => {
            // Debug builds check the list against the tests it replaces.
            #[cfg(debug_assertions)]
            let tested = crossed_as_tested(positions, distinct.clone(), region, known)?;
            let listed = crossed_as_listed(distinct, region, known);
            #[cfg(debug_assertions)]
            assert_eq!(listed, tested, "the listed crossings answer as the exact tests do");
            listed
        }
        false => crossed_as_tested(positions, distinct, region, known)?,
    };
    Ok(pairs.iter().map(|pair| crossed.contains(pair)).collect())
}

/// The pairs of sides (distinct) a face of one of which intersects a face of the other, as
/// the complete list of the level's crossings says.
fn crossed_as_listed(
    distinct: Vec<[Side; 2]>,
    region: &dyn Fn(Side) -> Vec<[u32; 3]>,
    known: &KnownCrossings,
) -> FxHashSet<[Side; 2]> {
    let mut regions: FxHashMap<Side, Vec<[u32; 3]>> = FxHashMap::default();
    for side in distinct.iter().flatten() {
        regions.entry(*side).or_insert_with(|| region(*side).into_iter().map(face_key).collect());
    }
    // A face is never listed as crossing itself, so a face on both sides does not count.
    let crossing = |[x, y]: &[Side; 2]| {
        let other = &regions[y];
        regions[x].iter().any(|&a| known.crossing(a).iter().any(|c| other.contains(c)))
    };
    distinct.into_iter().filter(|pair| crossing(pair)).collect()
}

/// [`crossed_as_listed`] by CGAL's exact test of every pair of their faces (each pair once),
/// counted in `known`.
fn crossed_as_tested(
    positions: &[glam::DVec3],
    distinct: Vec<[Side; 2]>,
    region: &dyn Fn(Side) -> Vec<[u32; 3]>,
    known: &mut KnownCrossings,
) -> Result<FxHashSet<[Side; 2]>> {
    let mut faces: Vec<[u32; 3]> = Vec::new();
    let mut index: FxHashMap<[u32; 3], u32> = FxHashMap::default();
    let mut regions: FxHashMap<Side, Vec<u32>> = FxHashMap::default();
    for side in distinct.iter().flatten() {
        regions.entry(*side).or_insert_with(|| {
            let slot = |t: [u32; 3]| {
                *index.entry(super::face_key(t)).or_insert_with(|| {
                    faces.push(t);
                    faces.len() as u32 - 1
                })
            };
            region(*side).into_iter().map(slot).collect()
        });
    }
    // Each pair of faces, one from each side, tested once (a face on both sides of a
    // pair, as when a plan's triangles cross each other, is not tested against itself).
    let across = |[x, y]: &[Side; 2]| {
        let (x, y) = (&regions[x], &regions[y]);
        x.iter().flat_map(move |&a| y.iter().filter(move |&&b| b != a).map(move |&b| [a.min(b), a.max(b)]))
    };
    let mut tests: Vec<[u32; 2]> = distinct.iter().flat_map(across).collect();
    tests.sort_unstable();
    tests.dedup();
    known.asked(tests.len());
    let crossing: FxHashSet<[u32; 2]> = listed_pairs_intersect(positions, &faces, &tests)?
        .into_iter()
        .zip(&tests)
        .filter_map(|(hit, pair)| hit.then_some(*pair))
        .collect();
    Ok(distinct.into_iter().filter(|pair| across(pair).any(|p| crossing.contains(&p))).collect())
}
