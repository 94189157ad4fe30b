//! Region refinement (thesis §4.6): the whole hierarchy refined to a chosen level, then only
//! a region's vertices inserted on the finer levels, so the region reaches the input's
//! resolution and the rest stays coarser. Vertices whose parameter face is missing (its
//! corners lie outside the region) are placed by Algorithm 2's search over the neighbouring
//! faces, and their degrees restored by Algorithm 3's flips; every operation is a split or
//! a flip of a manifold, so the result is conforming (no T-junctions) with the input's genus.

use super::{Hierarchy, LevelMesh, LevelReport, Refiner};
use crate::error::{Error, Result};

/// What [`refine_region`] made.
#[derive(Debug)]
pub struct RegionRefinement {
    /// The mesh, with input ids.
    pub mesh: LevelMesh,
    /// One report per refined level.
    pub reports: Vec<LevelReport>,
    /// Region vertices not in the result (no edge near them could take them).
    pub missing: Vec<u32>,
    /// Refinements run (more than one when self-intersections grew the refined set).
    pub rounds: usize,
    /// Self-intersecting face pairs left (0 unless [`MAX_ROUNDS`] were not enough).
    pub self_intersections: usize,
}

impl RegionRefinement {
    /// The reports summed over levels (`level` is the last one).
    pub fn totals(&self) -> LevelReport {
        LevelReport::total(&self.reports)
    }
}

/// Refines `hierarchy` whole up to `base_level` (0: the base domain; at most its
/// [`Hierarchy::steps`]), then only the vertices `inside` accepts (input ids) and their
/// dependencies up to the input's level. Where the result intersects itself (CGAL), the
/// removed vertices whose rings touch the offending faces are added too and the refinement
/// runs again, at most [`MAX_ROUNDS`] times (in the limit the offending parts reach the
/// input's resolution, which does not intersect itself if the input does not).
///
/// # Errors
/// [`Error::InvalidInput`] for a base level beyond the hierarchy; native errors from
/// OpenMesh and CGAL.
pub fn refine_region(hierarchy: &Hierarchy, base_level: usize, inside: &dyn Fn(u32) -> bool) -> Result<RegionRefinement> {
    let steps = hierarchy.steps();
    if base_level > steps {
        return Err(Error::InvalidInput(format!(
            "base level {base_level}: the hierarchy has levels 0 (base domain) to {steps} (the input)"
        )));
    }
    let n = hierarchy.positions.len();
    let rings = removal_rings(hierarchy);
    let mut wanted = with_dependencies(inside, n, &rings);
    let mut rounds = 0;
    loop {
        let (mesh, reports) = refine_selected(hierarchy, base_level, &wanted)?;
        let pairs = crate::ffi::self_intersections(&mesh.mesh)?;
        rounds += 1;
        let mut touched = vec![false; n];
        for face in pairs.iter().flatten() {
            for &v in &mesh.mesh.triangles[face.0 as usize] {
                touched[mesh.ids[v as usize] as usize] = true;
            }
        }
        let before = wanted.iter().filter(|&&w| w).count();
        for (v, ring) in rings.iter().enumerate() {
            if !wanted[v] && ring.iter().any(|&u| touched[u as usize]) {
                wanted[v] = true;
            }
        }
        close_under_dependencies(&mut wanted, &rings);
        let grown = wanted.iter().filter(|&&w| w).count() > before;
        if pairs.is_empty() || !grown || rounds == MAX_ROUNDS {
            let mut present = vec![false; n];
            for &id in &mesh.ids {
                present[id as usize] = true;
            }
            let missing = (0..n as u32).filter(|&v| inside(v) && !present[v as usize]).collect();
            return Ok(RegionRefinement { mesh, reports, missing, rounds, self_intersections: pairs.len() });
        }
    }
}

/// The vertices a region refinement inserts above its base level: those `inside` accepts
/// (input ids) and, recursively, the removal rings they need (as [`refine_region`] starts
/// from). A level-by-level refinement that selects these makes [`refine_region`]'s first
/// round; it does not grow the region where the result cuts itself, as later rounds do.
pub fn region_with_dependencies(hierarchy: &Hierarchy, inside: &dyn Fn(u32) -> bool) -> Vec<bool> {
    with_dependencies(inside, hierarchy.positions.len(), &removal_rings(hierarchy))
}

fn with_dependencies(inside: &dyn Fn(u32) -> bool, n: usize, rings: &[Vec<u32>]) -> Vec<bool> {
    let mut wanted: Vec<bool> = (0..n as u32).map(inside).collect();
    close_under_dependencies(&mut wanted, rings);
    wanted
}

/// How often [`refine_region`] grows the refined set around self-intersections.
pub const MAX_ROUNDS: usize = 8;

/// One refinement: whole to `base_level`, then the `wanted` vertices.
fn refine_selected(hierarchy: &Hierarchy, base_level: usize, wanted: &[bool]) -> Result<(LevelMesh, Vec<LevelReport>)> {
    let steps = hierarchy.steps();
    let mut refiner = Refiner::new(hierarchy)?;
    let mut reports = Vec::with_capacity(steps);
    crate::progress::report("refine", 0, steps as u64);
    while !refiner.is_finished() {
        let whole = refiner.level() < base_level;
        reports.push(refiner.refine_level(&|v| whole || wanted[v as usize])?);
        crate::progress::report("refine", refiner.level() as u64, steps as u64);
    }
    Ok((refiner.mesh()?, reports))
}

/// Each removed vertex's 1-ring on the level it was removed from: its parameter face, its
/// weld's diagonal and the ring vertices its degree flips restore (empty for base vertices).
fn removal_rings(hierarchy: &Hierarchy) -> Vec<Vec<u32>> {
    let mut rings = vec![Vec::new(); hierarchy.positions.len()];
    for r in &hierarchy.removals {
        let mut ring: Vec<u32> =
            r.local.face.iter().chain(&r.diagonal).chain(hierarchy.restore_of(r).iter().flatten()).copied().collect();
        ring.sort_unstable();
        ring.dedup();
        rings[r.vertex as usize] = ring;
    }
    rings
}

/// Adds, recursively, the removal rings of every wanted vertex, as a progressive mesh's
/// selective refinement needs its split's neighbours: with them present, most insertions
/// replay the recorded split and flips exactly, and the region's border grades into the
/// coarse rest instead of joining it by long folded triangles.
fn close_under_dependencies(wanted: &mut [bool], rings: &[Vec<u32>]) {
    let mut stack: Vec<u32> = (0..wanted.len() as u32).filter(|&v| wanted[v as usize]).collect();
    while let Some(v) = stack.pop() {
        for &u in &rings[v as usize] {
            if !wanted[u as usize] {
                wanted[u as usize] = true;
                stack.push(u);
            }
        }
    }
}
