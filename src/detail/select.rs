//! The vertex set VS of the deformation operator D(VS, l, f) (eq. 4.4): coordinate
//! restrictions, curvature thresholds, feature classes on or off (with Algorithm 4's
//! propagation), k-rings around seed vertices, and independent sets with k-ring exclusion
//! (§5.2.0.1). Clauses combine by "and"; the independent set thins the result last.

use glam::DVec3;

use super::level::{BoxFrame, LevelView};
use super::recipe::{CurvatureKind, FeatureMode, IndependentClause, Selection};
use crate::analysis::{FeatureClass, propagate_features};
use crate::error::{Error, Result};
use crate::noise::hash::hash_coords;

/// Evaluates `selection` on a level: one flag per vertex of `view.mesh`. `classes` holds
/// the input's feature class by id (vertices made by subdivision count as face vertices).
///
/// # Errors
/// [`Error::InvalidInput`] when a seed vertex is not in the level's mesh.
pub fn select(
    selection: &Selection,
    view: &LevelView,
    frame: &BoxFrame,
    classes: &[FeatureClass],
    seed: u64,
) -> Result<Vec<bool>> {
    let n = view.ids.len();
    let positions = &view.mesh.positions;
    let mut keep = vec![true; n];
    let mut restrict = |f: &dyn Fn(usize) -> bool| keep.iter_mut().enumerate().for_each(|(v, k)| *k = *k && f(v));
    if let Some(b) = &selection.r#box {
        let (lo, hi) = (DVec3::from_array(b.min), DVec3::from_array(b.max));
        restrict(&|v| {
            let q = frame.normalise(positions[v]);
            q.cmpge(lo).all() && q.cmple(hi).all()
        });
    }
    if let Some(s) = &selection.sphere {
        let (c, r) = (frame.point(s.center), s.radius * frame.diagonal);
        restrict(&|v| positions[v].distance(c) <= r);
    }
    if let Some(h) = &selection.half_space {
        let axis = h.axis.index();
        restrict(&|v| {
            let q = frame.normalise(positions[v])[axis];
            h.above.is_none_or(|a| q >= a) && h.below.is_none_or(|b| q <= b)
        });
    }
    if let Some(c) = &selection.curvature {
        let curv = &view.analysis()?.curvatures;
        let (values, scale) = match c.kind {
            CurvatureKind::Mean => (&curv.mean, frame.diagonal),
            CurvatureKind::Gaussian => (&curv.gaussian, frame.diagonal * frame.diagonal),
            CurvatureKind::K1 => (&curv.k1, frame.diagonal),
            CurvatureKind::K2 => (&curv.k2, frame.diagonal),
        };
        restrict(&|v| {
            let x = values[v] * scale;
            c.min.is_none_or(|m| x >= m) && c.max.is_none_or(|m| x <= m)
        });
    }
    if let Some(f) = &selection.features {
        let wanted: Vec<FeatureClass> = f.classes.iter().map(|c| c.class()).collect();
        let marks: Vec<bool> = view
            .ids
            .iter()
            .map(|&id| wanted.contains(classes.get(id as usize).unwrap_or(&FeatureClass::Face)))
            .collect();
        let (marks, _) = propagate_features(&view.adjacency, &marks, f.propagate);
        let on = f.mode == FeatureMode::On;
        restrict(&|v| marks[v] == on);
    }
    if let Some(a) = &selection.around {
        let mut centres = Vec::new();
        for &id in &a.vertices {
            let local = view.ids.binary_search(&id).map_err(|_| {
                Error::InvalidInput(format!("select.around: vertex {id} is not in the mesh at level {}", view.level))
            })?;
            centres.push(local);
        }
        for &p in &a.points {
            let target = frame.point(p);
            let nearest = (0..n).min_by(|&u, &w| {
                positions[u].distance_squared(target).total_cmp(&positions[w].distance_squared(target)).then(u.cmp(&w))
            });
            centres.extend(nearest);
        }
        let reach = view.rings_from(&centres, a.rings);
        restrict(&|v| reach[v].is_some());
    }
    if let Some(ind) = &selection.independent {
        keep = independent_set(view, &keep, ind, seed);
    }
    Ok(keep)
}

/// A maximal independent set of the candidates: visiting them in order (by id, or in a
/// seeded random order), each chosen vertex excludes its k-ring (§5.2.0.1).
pub fn independent_set(view: &LevelView, candidates: &[bool], clause: &IndependentClause, seed: u64) -> Vec<bool> {
    let mut order: Vec<usize> = (0..candidates.len()).filter(|&v| candidates[v]).collect();
    if clause.shuffle {
        order.sort_by_key(|&v| (hash_coords(seed, &[i64::from(view.ids[v])]), v));
    }
    let mut excluded = vec![false; candidates.len()];
    let mut chosen = vec![false; candidates.len()];
    for v in order {
        if excluded[v] {
            continue;
        }
        chosen[v] = true;
        excluded[v] = true;
        for w in view.adjacency.k_ring(v, clause.exclusion) {
            excluded[w as usize] = true;
        }
    }
    chosen
}
