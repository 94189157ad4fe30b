//! Feature-sensitive four-face-cluster simplification (thesis §3.1.7, §4.4.1, Algorithm 2
//! of §3.1.7): per level, vertices ranked by E(v) (eq. 4.1), a maximal independent set of
//! clusters chosen greedily, each brought to degree 4 by spoke flips and removed by an edge
//! weld, all applied to the OpenMesh store in one batched call per operation.

use std::time::Instant;

use rayon::prelude::*;

use rustc_hash::FxHashSet;

use super::cluster::{
    ClusterPlan, ClusterRules, LevelGeometry, apply_plan, estimate_error, plan_cluster, plan_still_applies,
};
use super::param::ParamBuckets;
use super::rings::Rings;
use super::{BuildStages, Hierarchy, KeepFeatures, LevelMesh, Removal, SimplifyOptions, used_vertices};
use crate::analysis::{FaceGeometry, FeatureClass, classify, voting_tensors};
use crate::error::{Error, Result};
use crate::ffi::{self, CollapseOptions, HalfEdgeMesh, OpStatus};
use crate::mesh::{Adjacency, FaceId, Mesh, ValidationReport, is_degenerate_face};

/// Builds the 4-k hierarchy of `mesh`: simplification down to the base domain, with the
/// parametrization of every removed vertex.
///
/// # Errors
/// [`Error::InvalidInput`] for an inconsistent mesh or options; [`Error::Topology`] for a
/// non-manifold mesh; [`Error::Native`] if OpenMesh or CGAL refuse it.
pub fn build(mesh: &Mesh, options: &SimplifyOptions) -> Result<Hierarchy> {
    let started = Instant::now();
    let mut stages = BuildStages::default();
    let mut clock = Instant::now();
    prepare_input(mesh)?;
    let n = mesh.vertex_count();
    let mut store = HalfEdgeMesh::from_mesh(mesh)?;
    let mut quadrics = ffi::vertex_quadrics(mesh, 100.0)?;
    let (kept, feature_vertices) = unremovable_vertices(mesh, options)?;
    let rules = ClusterRules { removal_weight: options.removal_weight, swap_weight: options.swap_weight };
    let diagonal = mesh.bounding_box().map_or(0.0, |(lo, hi)| (hi - lo).length());
    let max_error = options.max_error.map(|f| (f * diagonal).powi(2));

    let referenced = used_vertices(n, &mesh.triangles);
    let mut live: Vec<u32> = (0..n as u32).filter(|&v| referenced[v as usize]).collect();
    let mut params = ParamBuckets::new(n);
    let mut removals: Vec<Removal> = Vec::new();
    let mut restore: Vec<[u32; 2]> = Vec::new();
    let mut step_starts = vec![0];
    let mut levels = Vec::new();
    if options.record_levels {
        levels.push(LevelMesh::compact(&mesh.positions, &exported_triangles(&store)?));
    }
    let mut locked = vec![false; n];
    let mut rings = Rings::fetch(&store, &live, n)?;
    lap(&mut clock, &mut stages.prepare);
    while options.levels.is_none_or(|l| step_starts.len() - 1 < l) {
        if options.target_vertices.is_some_and(|t| live.len() <= t) {
            break;
        }
        let geometry = LevelGeometry { positions: &mesh.positions, quadrics: &quadrics };
        let order = candidate_order(&live, &rings, &kept, geometry, &rules);
        lap(&mut clock, &mut stages.ranking);
        let level_faces = if options.prevent_intersections { rings.faces(&live) } else { Vec::new() };
        lap(&mut clock, &mut stages.guard);
        rings.checkpoint();
        let mut plans =
            select_clusters(&order, &mut rings, geometry, &rules, &mut locked, live.len(), options, max_error)?;
        for &v in &live {
            locked[v as usize] = false;
        }
        lap(&mut clock, &mut stages.planning);
        if options.prevent_intersections {
            plans = guard_plans(&mesh.positions, &level_faces, plans, &mut rings)?;
            lap(&mut clock, &mut stages.guard);
        }
        rings.commit();
        if plans.is_empty() {
            break;
        }
        apply_to_store(&mut store, &plans)?;
        lap(&mut clock, &mut stages.store);
        let step = (step_starts.len() - 1) as u32;
        for plan in &plans {
            let point = params.apply_removal(plan);
            let restore_start = restore.len() as u32;
            restore.extend(plan.triangles[..plan.flips.len()].iter().rev().map(|ear| [ear[0], ear[1]]));
            removals.push(Removal {
                vertex: plan.vertex,
                step,
                degree: plan.ring.len() as u32,
                local: point,
                diagonal: plan.diagonal,
                restore: [restore_start, restore.len() as u32],
            });
            let q = quadrics[plan.vertex as usize];
            for end in plan.diagonal {
                quadrics[end as usize].add_scaled(&q, 0.5);
            }
        }
        let removed: FxHashSet<u32> = plans.iter().map(|p| p.vertex).collect();
        live.retain(|v| !removed.contains(v));
        step_starts.push(removals.len());
        lap(&mut clock, &mut stages.parametrization);
        if options.record_levels {
            levels.push(LevelMesh::compact(&mesh.positions, &exported_triangles(&store)?));
            lap(&mut clock, &mut stages.export);
        }
    }
    let base_triangles = exported_triangles(&store)?;
    check_agreement(&base_triangles, &rings.faces(&live))?;
    lap(&mut clock, &mut stages.export);
    Ok(Hierarchy {
        positions: mesh.positions.clone(),
        input_triangles: mesh.triangles.clone(),
        base_triangles,
        removals,
        restore,
        step_starts,
        params: params.into_points(),
        kept,
        feature_vertices,
        levels,
        fix_threshold: options.fix_threshold_degrees.to_radians(),
        seconds: started.elapsed().as_secs_f64(),
        stages,
    })
}

/// The store's faces must be the rings' faces: planning edits the rings, OpenMesh carries
/// out the same operations (checking each), so a difference is a bug.
fn check_agreement(store_faces: &[[u32; 3]], ring_faces: &[[u32; 3]]) -> Result<()> {
    let sorted = |faces: &[[u32; 3]]| {
        let mut keys: Vec<[u32; 3]> = faces.iter().map(|&t| super::face_key(t)).collect();
        keys.sort_unstable();
        keys
    };
    if sorted(store_faces) != sorted(ring_faces) {
        return Err(Error::Internal(format!(
            "OpenMesh holds {} faces and the planning rings {} different ones",
            store_faces.len(),
            ring_faces.len()
        )));
    }
    Ok(())
}

/// Adds the time since `clock` to `stage` and restarts the clock.
fn lap(clock: &mut Instant, stage: &mut f64) {
    let now = Instant::now();
    *stage += (now - *clock).as_secs_f64();
    *clock = now;
}

/// Input preparation (§4.3): the mesh must be a consistently oriented manifold triangle
/// mesh without degenerate faces or unreferenced vertices (polygons are triangulated by the
/// readers; [`crate::mesh::repair`] fixes the rest); degree-4 clusters are then made by
/// flips during simplification.
fn prepare_input(mesh: &Mesh) -> Result<()> {
    mesh.check()?;
    if mesh.face_count() == 0 {
        return Err(Error::InvalidInput("the mesh has no faces to simplify".into()));
    }
    let report = ValidationReport::of(mesh);
    let refuse =
        |msg: String, faces: Vec<FaceId>| Err(Error::Topology { msg: format!("{msg}; --repair fixes it"), faces });
    if !report.is_manifold() || report.inconsistently_oriented_edges > 0 {
        let msg = format!(
            "the mesh is not an oriented manifold ({} non-manifold edges, {} non-manifold vertices, {} inconsistently oriented edges); --repair splits and orients it where the surface is orientable",
            report.non_manifold_edges, report.non_manifold_vertices, report.inconsistently_oriented_edges
        );
        return Err(Error::Topology { msg, faces: Vec::new() });
    }
    if report.degenerate_faces > 0 {
        let faces: Vec<FaceId> =
            (0..mesh.face_count()).filter(|&f| is_degenerate_face(mesh, f)).map(|f| FaceId(f as u32)).collect();
        return refuse(
            format!(
                "{} face(s) have zero area, first face {} (the hierarchy cannot parametrize over them)",
                faces.len(),
                faces[0].0
            ),
            faces,
        );
    }
    if report.unreferenced_vertices > 0 {
        let used = used_vertices(mesh.vertex_count(), &mesh.triangles);
        let first = used.iter().position(|u| !u).expect("an unreferenced vertex");
        return refuse(
            format!("{} vertex/vertices belong to no face, first vertex {first}", report.unreferenced_vertices),
            Vec::new(),
        );
    }
    Ok(())
}

/// Vertices never removed: feature vertices (§4.4.1.1, Algorithm 1 classes) and those
/// the user marked. Returns the flags and the number of feature vertices.
fn unremovable_vertices(mesh: &Mesh, options: &SimplifyOptions) -> Result<(Vec<bool>, usize)> {
    let n = mesh.vertex_count();
    let mut kept = vec![false; n];
    let mut features = 0;
    if options.keep_features != KeepFeatures::None {
        let adjacency = Adjacency::of(mesh);
        let classes =
            classify(&adjacency, &voting_tensors(mesh, &adjacency, &FaceGeometry::of(mesh)), &Default::default());
        for (v, class) in classes.into_iter().enumerate() {
            let keep = match options.keep_features {
                KeepFeatures::None => false,
                KeepFeatures::Strong => class.is_sharp(),
                KeepFeatures::All => class != FeatureClass::Face,
            };
            if keep {
                kept[v] = true;
                features += 1;
            }
        }
    }
    for &v in &options.keep_vertices {
        let slot = kept
            .get_mut(v as usize)
            .ok_or_else(|| Error::InvalidInput(format!("vertex {v} marked to keep is out of range ({n} vertices)")))?;
        *slot = true;
    }
    Ok((kept, features))
}

/// Removable candidates in order of increasing estimated E(v), ties by vertex id.
fn candidate_order(
    live: &[u32],
    rings: &Rings,
    kept: &[bool],
    geometry: LevelGeometry<'_>,
    rules: &ClusterRules,
) -> Vec<u32> {
    let mut ranked: Vec<(f64, u32)> = live
        .par_iter()
        .filter(|&&v| !kept[v as usize] && !rings.is_boundary(v) && rings.degree(v) >= 4)
        .map(|&v| (estimate_error(v, rings, geometry, rules), v))
        .collect();
    ranked.par_sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    ranked.into_iter().map(|(_, v)| v).collect()
}

/// Greedy maximal independent set of clusters (Velho & Gomes' marking): take the cheapest
/// unmarked vertex, plan its cluster, and mark it and its ring.
#[allow(clippy::too_many_arguments)]
fn select_clusters(
    order: &[u32],
    rings: &mut Rings,
    geometry: LevelGeometry<'_>,
    rules: &ClusterRules,
    locked: &mut [bool],
    live: usize,
    options: &SimplifyOptions,
    max_error: Option<f64>,
) -> Result<Vec<ClusterPlan>> {
    let mut plans: Vec<ClusterPlan> = Vec::new();
    for &v in order {
        if options.target_vertices.is_some_and(|t| live - plans.len() <= t) {
            break;
        }
        if locked[v as usize] {
            continue;
        }
        let Some(plan) = plan_cluster(v, rings, geometry, rules) else { continue };
        if max_error.is_some_and(|m| plan.error > m) {
            continue;
        }
        apply_plan(&plan, rings)?;
        locked[v as usize] = true;
        for &r in &plan.ring {
            locked[r as usize] = true;
        }
        plans.push(plan);
    }
    Ok(plans)
}

/// The intersection guard: leaves out the plans whose new triangles would intersect the
/// level's surface as planned (CGAL's exact predicates; intersections already in the level
/// are not counted). The offending plans are dropped and the others replayed on the rings
/// in their order, dropping those that no longer apply without the dropped ones
/// ([`plan_still_applies`]); the faces that come back are then checked against the rest,
/// until nothing offends. Plans are never re-planned, so each round after the first checks
/// only the restored faces.
fn guard_plans(
    positions: &[glam::DVec3],
    level_faces: &[[u32; 3]],
    mut plans: Vec<ClusterPlan>,
    rings: &mut Rings,
) -> Result<Vec<ClusterPlan>> {
    let mut restored = None;
    loop {
        let offending = intersecting_plans(positions, level_faces, &plans, restored.as_ref())?;
        if offending.is_empty() {
            return Ok(plans);
        }
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
    let (mut kept, mut kept_owner, mut added, mut added_owner) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for t in level_faces {
        if t.iter().any(|v| planned.contains(v)) {
            continue;
        }
        if restored.is_some_and(|r| t.iter().any(|v| r.contains(v))) {
            added.push(*t);
            added_owner.push(None);
        } else {
            kept.push(*t);
            kept_owner.push(None);
        }
    }
    let (faces, owners) =
        if restored.is_some() { (&mut kept, &mut kept_owner) } else { (&mut added, &mut added_owner) };
    for plan in plans {
        faces.extend(&plan.triangles);
        owners.extend(std::iter::repeat_n(Some(plan.vertex), plan.triangles.len()));
    }
    let owner =
        |t: u32| if (t as usize) < kept.len() { kept_owner[t as usize] } else { added_owner[t as usize - kept.len()] };
    let mut offending = FxHashSet::default();
    for pair in ffi::added_triangle_intersections(positions, &kept, &added)? {
        offending.extend(pair.iter().filter_map(|&t| owner(t)));
    }
    Ok(offending)
}

/// Replays the planned flips, then the welds, on the store (one call each).
fn apply_to_store(store: &mut HalfEdgeMesh, plans: &[ClusterPlan]) -> Result<()> {
    let flips: Vec<[u32; 2]> = plans.iter().flat_map(|p| p.flips.iter().map(move |&a| [p.vertex, a])).collect();
    expect_done("flip", &flips, &store.flip_edges(&flips)?)?;
    let welds: Vec<[u32; 2]> = plans.iter().map(|p| [p.vertex, p.weld_to]).collect();
    let status = store.collapse_halfedges(&welds, CollapseOptions { required_degree: 4, check_normals: false })?;
    expect_done("weld", &welds, &status)
}

/// Planning checks every condition OpenMesh checks, so a refusal is a bug.
pub(super) fn expect_done(what: &str, pairs: &[[u32; 2]], status: &[OpStatus]) -> Result<()> {
    match status.iter().position(|&s| s != OpStatus::Done) {
        None => Ok(()),
        Some(i) => Err(Error::Internal(format!(
            "OpenMesh refused the planned {what} {}–{} ({:?})",
            pairs[i][0], pairs[i][1], status[i]
        ))),
    }
}

/// The store's live faces in store vertex indices.
pub(super) fn exported_triangles(store: &HalfEdgeMesh) -> Result<Vec<[u32; 3]>> {
    let exported = store.export()?;
    let mut store_index = vec![0u32; exported.mesh.vertex_count()];
    for (i, &e) in exported.vertex_remap.iter().enumerate() {
        if e != ffi::INVALID_INDEX {
            store_index[e as usize] = i as u32;
        }
    }
    Ok(exported.mesh.triangles.iter().map(|t| t.map(|v| store_index[v as usize])).collect())
}
