//! Refinement with a Python operator at every level (the thesis' D(VS, l, f), eq. 4.4, with
//! f written in Python): the C++ `Hierarchy::refine(op)`'s loop, each level handed to the
//! operator as numpy arrays, its moved positions taken back before the next level inserts
//! its vertices on the moved surface (§4.5.1).

use std::sync::Arc;

use asperity::analysis::SurfaceAnalysis;
use asperity::detail::LevelView;
use asperity::hierarchy::{Hierarchy, LevelMesh, LevelReport, Refiner};
use numpy::{PyArray1, PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{positions_array, triangles_array, vectors_array};
use crate::interrupt::Progress;
use crate::{InputError, to_py};

/// One refinement level as `Hierarchy.refine(op=...)`'s operator sees it: `level` (0 is
/// the base domain, `level_count - 1` the input's), `positions` (n, 3) float64 — writable:
/// move them in place or assign new ones, the next level inserts its vertices on the moved
/// surface — `faces` (m, 3) uint32, `ids` (each vertex's input id), `normals` (unit,
/// angle-weighted, of the level as given), `vertex_levels` (the level at which each vertex
/// first appears, 0 for a base vertex), and `analysis()`: curvatures and feature classes of
/// the level as given, `asperity.analyze`'s keys, computed on first call.
#[pyclass(module = "asperity._asperity")]
pub struct Level {
    /// Refinement level: 0 is the base domain, `level_count - 1` the input's.
    #[pyo3(get)]
    level: usize,
    #[pyo3(get)]
    level_count: usize,
    /// (n, 3) float64, writable; read back after the operator.
    #[pyo3(get, set)]
    positions: Py<PyAny>,
    #[pyo3(get)]
    faces: Py<PyArray2<u32>>,
    /// The caller's vertex id of each vertex.
    #[pyo3(get)]
    ids: Py<PyArray1<u32>>,
    #[pyo3(get)]
    normals: Py<PyArray2<f64>>,
    #[pyo3(get)]
    vertex_levels: Py<PyArray1<u32>>,
    view: Arc<LevelView>,
}

#[pymethods]
impl Level {
    /// Curvatures and feature classes of the level as given (before any move), computed
    /// on first call: the keys of `asperity.analyze`.
    fn analysis<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let view = Arc::clone(&self.view);
        let analysis = py.detach(move || view.analysis().cloned()).map_err(to_py)?;
        analysis_dict(py, &analysis)
    }

    fn __len__(&self) -> usize {
        self.view.ids.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Level({} of {}: {} vertices, {} faces)",
            self.level,
            self.level_count,
            self.view.ids.len(),
            self.view.mesh.face_count()
        )
    }
}

/// A surface analysis as `asperity.analyze` returns it.
pub fn analysis_dict<'py>(py: Python<'py>, analysis: &SurfaceAnalysis) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let c = &analysis.curvatures;
    out.set_item("normals", vectors_array(py, analysis.normals.clone()))?;
    out.set_item("mean_curvature", PyArray1::from_vec(py, c.mean.clone()))?;
    out.set_item("gaussian_curvature", PyArray1::from_vec(py, c.gaussian.clone()))?;
    out.set_item("k1", PyArray1::from_vec(py, c.k1.clone()))?;
    out.set_item("k2", PyArray1::from_vec(py, c.k2.clone()))?;
    let classes: Vec<u8> = analysis.classes.iter().map(|&k| k as u8).collect();
    out.set_item("feature_class", PyArray1::from_vec(py, classes))?;
    out.set_item("diffusion", vectors_array(py, analysis.diffusion()))?;
    Ok(out)
}

/// Which vertices each level inserts: every one below `base_level`, then those `wanted`
/// marks (all when `None`).
pub struct Selection {
    pub base_level: usize,
    pub wanted: Option<Vec<bool>>,
}

/// Refines `hierarchy` level by level, calling `op` with each level (the base domain
/// first, the input's level last) and taking back its positions; `caller_id` maps the
/// hierarchy's vertex ids to the caller's. An exception the operator raises is returned
/// unchanged.
pub fn refine_with_operator(
    py: Python<'_>,
    hierarchy: &Hierarchy,
    op: &Bound<'_, PyAny>,
    selection: &Selection,
    caller_id: &dyn Fn(u32) -> u32,
    progress: &Progress,
) -> PyResult<(LevelMesh, Vec<LevelReport>)> {
    let steps = hierarchy.steps();
    // The Rust stages run with the GIL released (other Python threads go on); the
    // operator runs with it.
    let mut refiner = py.detach(|| Refiner::new(hierarchy)).map_err(to_py)?;
    refiner.set_follow_deformation(true);
    let appear = hierarchy.appearance_levels();
    let mut reports = Vec::with_capacity(steps);
    loop {
        let level = refiner.level();
        // A `&mut` crosses to the detached closure: the refiner is Send, not Sync.
        let (r, appear) = (&mut refiner, &appear);
        let view = py
            .detach(move || r.mesh().map(|mesh| LevelView::new(level, steps - level, mesh).with_appearance(appear)))
            .map_err(to_py)?;
        let arrays = Level::of(py, view, steps + 1, caller_id)?;
        let ids = arrays.view.ids.clone();
        let handle = Bound::new(py, arrays)?;
        op.call1((handle.clone(),))?;
        let moved = positions_back(py, &handle.borrow(), level)?;
        let all = refiner.positions_mut();
        for (&id, p) in ids.iter().zip(moved) {
            all[id as usize] = p;
        }
        py.check_signals()?;
        if refiner.is_finished() {
            break;
        }
        let whole = level < selection.base_level;
        let wanted = selection.wanted.as_deref();
        let select = |v: u32| whole || wanted.is_none_or(|w| w[v as usize]);
        let r = &mut refiner;
        reports.push(py.detach(move || r.refine_level(&select)).map_err(to_py)?);
        level_done(py, progress, refiner.level() as u64, steps as u64)?;
    }
    let r = &mut refiner;
    Ok((py.detach(move || r.mesh()).map_err(to_py)?, reports))
}

/// Reports a refined level to `progress`: printed, or asked of the callback (False:
/// `Cancelled`; its exception arrives unchanged).
fn level_done(py: Python<'_>, progress: &Progress, done: u64, total: u64) -> PyResult<()> {
    match progress {
        Progress::Off => Ok(()),
        Progress::Print => {
            crate::interrupt::print_progress("refine", done * 100 / total.max(1), done >= total);
            Ok(())
        }
        Progress::Call(callback) => {
            let answer = callback.call1(py, ("refine", done, total))?;
            if crate::interrupt::says_stop(answer.bind(py)) {
                let error = asperity::Error::Cancelled { stage: "refine".into(), done, total };
                return Err(crate::Cancelled::new_err(error.to_string()));
            }
            Ok(())
        }
    }
}

impl Level {
    fn of(py: Python<'_>, view: LevelView, level_count: usize, caller_id: &dyn Fn(u32) -> u32) -> PyResult<Self> {
        let ids: Vec<u32> = view.ids.iter().map(|&v| caller_id(v)).collect();
        Ok(Level {
            level: view.level,
            level_count,
            positions: positions_array(py, view.mesh.positions.clone()).into_any().unbind(),
            faces: triangles_array(py, view.mesh.triangles.clone()).unbind(),
            ids: PyArray1::from_vec(py, ids).unbind(),
            normals: vectors_array(py, view.normals.clone()).unbind(),
            vertex_levels: PyArray1::from_vec(py, view.appear.clone()).unbind(),
            view: Arc::new(view),
        })
    }
}

/// The level's positions after the operator: (n, 3) float64, finite.
fn positions_back(py: Python<'_>, level: &Level, l: usize) -> PyResult<Vec<glam::DVec3>> {
    let py_positions = level.positions.bind(py);
    let array: PyReadonlyArray2<'_, f64> = py_positions
        .extract()
        .map_err(|_| InputError::new_err(format!("level {l}: positions must stay an (n, 3) float64 array")))?;
    let n = level.view.ids.len();
    let rows = array.as_array();
    let shape = rows.shape();
    if shape != [n, 3] {
        return Err(InputError::new_err(format!(
            "level {l}: positions has shape ({}, {}) for {n} vertices",
            shape[0], shape[1]
        )));
    }
    let mut out = Vec::with_capacity(n);
    for (k, row) in rows.outer_iter().enumerate() {
        let p = glam::DVec3::new(row[0], row[1], row[2]);
        if !p.is_finite() {
            return Err(InputError::new_err(format!("level {l}: position {k} is not finite")));
        }
        out.push(p);
    }
    Ok(out)
}
