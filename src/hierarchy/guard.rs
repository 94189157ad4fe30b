//! The intersection guard of simplification: a level's planned retriangulations must not
//! cut the surface they join (checked with CGAL's exact predicates through
//! [`super::added_triangle_intersections`]); the plans that would are left for a later level.

use rustc_hash::{FxHashMap, FxHashSet};

use super::plan::{ClusterPlan, apply_plan, plan_still_applies};
use super::rings::Rings;
use crate::error::Result;

/// The intersection guard: leaves out the plans whose new triangles would intersect the
/// level's surface as planned (CGAL's exact predicates; intersections already in the level
/// are not counted, nor a planned triangle's crossing of a face that the faces it replaces
/// already crossed: see [`crossings_before`]). The offending plans are dropped and the others replayed on the rings
/// in their order, dropping those that no longer apply without the dropped ones
/// ([`plan_still_applies`]); the faces that come back are then checked against the rest,
/// until nothing offends. Plans are never re-planned, so each round after the first checks
/// only the restored faces. Returns the plans kept and the vertices whose plans offended.
pub(super) fn guard_plans(
    positions: &[glam::DVec3],
    level_faces: &[[u32; 3]],
    mut plans: Vec<ClusterPlan>,
    rings: &mut Rings,
) -> Result<(Vec<ClusterPlan>, FxHashSet<u32>)> {
    let mut restored = None;
    let mut offenders = FxHashSet::default();
    loop {
        let offending = intersecting_plans(positions, level_faces, &plans, restored.as_ref())?;
        if offending.is_empty() {
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

/// The planned vertices whose new triangles intersect the surface. With `restored` (the
/// vertices of plans just dropped), only their star faces, which come back, are checked
/// against the rest: the other pairs were checked by an earlier round.
fn intersecting_plans(
    positions: &[glam::DVec3],
    level_faces: &[[u32; 3]],
    plans: &[ClusterPlan],
    restored: Option<&FxHashSet<u32>>,
) -> Result<FxHashSet<u32>> {
    let planned: FxHashSet<u32> = plans.iter().map(|p| p.vertex).collect();
    let (mut kept, mut added) = (Vec::new(), Vec::new());
    for t in level_faces {
        if t.iter().any(|v| planned.contains(v)) {
            continue;
        }
        if restored.is_some_and(|r| t.iter().any(|v| r.contains(v))) {
            added.push(*t);
        } else {
            kept.push(*t);
        }
    }
    // The plans' triangles go last on their side; `owners` names each one's plan.
    let faces = if restored.is_some() { &mut kept } else { &mut added };
    let first_planned = faces.len();
    let mut owners = Vec::new();
    for plan in plans {
        faces.extend(&plan.triangles);
        owners.extend(std::iter::repeat_n(plan.vertex, plan.triangles.len()));
    }
    let first_planned = if restored.is_some() { first_planned } else { kept.len() + first_planned };
    let owner = |t: u32| (t as usize).checked_sub(first_planned).and_then(|i| owners.get(i).copied());
    let pairs = super::added_triangle_intersections(positions, &kept, &added)?;
    if pairs.is_empty() {
        return Ok(FxHashSet::default());
    }
    let combined: Vec<[u32; 3]> = kept.iter().chain(&added).copied().collect();
    let stars: FxHashMap<u32, Vec<[u32; 3]>> = {
        let offending: FxHashSet<u32> = pairs.iter().flatten().filter_map(|&t| owner(t)).collect();
        let mut stars: FxHashMap<u32, Vec<[u32; 3]>> = offending.iter().map(|&v| (v, Vec::new())).collect();
        for t in level_faces {
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
    let region = |t: u32| -> Vec<[u32; 3]> {
        match owner(t) {
            Some(v) => stars[&v].clone(),
            None => vec![combined[t as usize]],
        }
    };
    let before = crossings_before(positions, &pairs, &region)?;
    let mut offending = FxHashSet::default();
    for (k, pair) in pairs.iter().enumerate() {
        if !before[k] {
            offending.extend(pair.iter().filter_map(|&t| owner(t)));
        }
    }
    Ok(offending)
}

/// For each intersecting pair of a level as planned, whether the surface already crossed
/// itself there: whether a face of one side's `region` (the faces it replaces, or itself)
/// intersects a face of the other's in the level before the plans. Inputs whose parts
/// interpenetrate or touch (assemblies, scans with overlapping sheets) keep those
/// crossings at every level; the guard refuses only crossings the plans would make (#34).
fn crossings_before(
    positions: &[glam::DVec3],
    pairs: &[[u32; 2]],
    region: &dyn Fn(u32) -> Vec<[u32; 3]>,
) -> Result<Vec<bool>> {
    let mut faces: Vec<[u32; 3]> = Vec::new();
    let mut index: FxHashMap<[u32; 3], u32> = FxHashMap::default();
    let mut slot = |t: [u32; 3], faces: &mut Vec<[u32; 3]>| {
        *index.entry(super::face_key(t)).or_insert_with(|| {
            faces.push(t);
            faces.len() as u32 - 1
        })
    };
    let sides: Vec<[Vec<u32>; 2]> = pairs
        .iter()
        .map(|&[a, b]| [region(a), region(b)].map(|r| r.into_iter().map(|t| slot(t, &mut faces)).collect()))
        .collect();
    let crossing: FxHashSet<[u32; 2]> = super::added_triangle_intersections(positions, &[], &faces)?
        .into_iter()
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    Ok(sides
        .iter()
        .map(|[x, y]| x.iter().any(|&a| y.iter().any(|&b| crossing.contains(&[a.min(b), a.max(b)]))))
        .collect())
}
