//! `asperity._asperity`: the native layer of the Python package. Every function takes
//! numpy arrays and its options as the JSON object of a library request's fields (the
//! terrain, noise, the hierarchy, detail, analyze, compare, render, clouds: read strictly
//! by `asperity::request::from_fields`, #38, with no argv between). It calls the same
//! library functions the command line calls, so
//! results are identical bit for bit and errors carry the same one-line messages, each
//! option spelt as its keyword. No logic of its own: see `python/asperity/__init__.py` for
//! the public API and its documentation.

mod arrays;
mod interrupt;
mod level;

use std::path::PathBuf;

use numpy::{PyArray1, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use arrays::{heights_array, mesh_of, points_of, positions_array, triangles_array, vectors_array};
use asperity::detail::DetailOptions;
use asperity::hierarchy::HierarchyRequest;
use asperity::mesh::Mesh;
use asperity::noise::NoiseRequest;
use asperity::request::{Spelling, from_fields};
use asperity::terrain::TerrainRequest;
use interrupt::{Progress, run};

pyo3::create_exception!(
    _asperity,
    InputError,
    PyValueError,
    "Bad input: a file, a mesh, a recipe or a parameter asperity cannot use (the command line's exit 2)."
);
pyo3::create_exception!(
    _asperity,
    InternalError,
    PyRuntimeError,
    "A failure inside asperity or its native libraries (the command line's exit 1): please report it."
);

pyo3::create_exception!(
    _asperity,
    Cancelled,
    pyo3::exceptions::PyException,
    "The call's progress callback returned False: the call stopped there and left nothing half-made."
);

/// The Python exception of an asperity error, with the command line's message.
fn to_py(error: asperity::Error) -> PyErr {
    if let asperity::Error::Cancelled { .. } = error {
        Cancelled::new_err(error.to_string())
    } else if error.exit_code() == 2 {
        InputError::new_err(error.to_string())
    } else {
        InternalError::new_err(error.to_string())
    }
}

/// A mesh repaired first when `repair` (the command line's `--repair`).
fn repaired(mesh: Mesh, repair: bool) -> asperity::Result<Mesh> {
    if repair { asperity::mesh::repair(&mesh).map(|(m, _)| m) } else { Ok(mesh) }
}

/// Reads a mesh file: positions, triangles, normals, colours, scalars by name, notes.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn read<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<(
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<u32>>,
    Option<Bound<'py, PyArray2<f64>>>,
    Option<Bound<'py, PyArray2<u8>>>,
    Bound<'py, PyDict>,
    Vec<String>,
)> {
    let mut outcome = run(py, false, move || asperity::io::read(&path))?;
    // The Python mesh has no place for them yet: said, not dropped unseen.
    if outcome.mesh.uvs.is_some() || outcome.mesh.materials.is_some() {
        outcome
            .notes
            .push("texture coordinates and materials are not handed to Python (the command line keeps them)".into());
    }
    let mesh = outcome.mesh;
    let scalars = PyDict::new(py);
    for (name, values) in mesh.scalars {
        scalars.set_item(name, PyArray1::from_vec(py, values))?;
    }
    let normals = mesh.normals.map(|n| vectors_array(py, n));
    let colors = mesh.colors.map(|c| arrays::colors_array(py, c));
    Ok((
        positions_array(py, mesh.positions),
        triangles_array(py, mesh.triangles),
        normals,
        colors,
        scalars,
        outcome.notes,
    ))
}

/// Writes a mesh file in the format its extension names.
#[pyfunction]
#[pyo3(signature = (path, positions, triangles, normals=None, colors=None, scalars=None, ascii=false))]
#[allow(clippy::too_many_arguments)]
fn write(
    py: Python<'_>,
    path: PathBuf,
    positions: PyReadonlyArray2<'_, f64>,
    triangles: PyReadonlyArray2<'_, u32>,
    normals: Option<PyReadonlyArray2<'_, f64>>,
    colors: Option<PyReadonlyArray2<'_, u8>>,
    scalars: Option<Vec<(String, PyReadonlyArray1<'_, f64>)>>,
    ascii: bool,
) -> PyResult<()> {
    let mut mesh = mesh_of(&positions, &triangles)?;
    let n = mesh.vertex_count();
    if let Some(normals) = normals {
        mesh.normals = Some(arrays::vectors_of(&normals, n, "normals")?);
    }
    if let Some(colors) = colors {
        mesh.colors = Some(arrays::colors_of(&colors, n)?);
    }
    for (name, values) in scalars.unwrap_or_default() {
        let values = values.as_slice().map_err(|e| InputError::new_err(format!("{name}: {e}")))?.to_vec();
        if values.len() != n {
            return Err(InputError::new_err(format!("attribute {name} has {} values for {n} vertices", values.len())));
        }
        mesh.scalars.insert(name, values);
    }
    let options = asperity::io::WriteOptions { ascii };
    run(py, false, move || asperity::io::write(&mesh, &path, options))
}

/// The validation report of a mesh, as JSON.
#[pyfunction]
fn info(
    py: Python<'_>,
    positions: PyReadonlyArray2<'_, f64>,
    triangles: PyReadonlyArray2<'_, u32>,
) -> PyResult<String> {
    let mesh = mesh_of(&positions, &triangles)?;
    let report = run(py, false, move || Ok(mesh.validate()))?;
    Ok(serde_json::to_string(&report).expect("a report serialises"))
}

/// Repairs a mesh: the repaired positions and triangles, and the report as JSON.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn repair<'py>(
    py: Python<'py>,
    positions: PyReadonlyArray2<'py, f64>,
    triangles: PyReadonlyArray2<'py, u32>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<u32>>, String)> {
    let mesh = mesh_of(&positions, &triangles)?;
    let (mesh, report) = run(py, false, move || asperity::mesh::repair(&mesh))?;
    let report = serde_json::to_string(&report).expect("a report serialises");
    Ok((positions_array(py, mesh.positions), triangles_array(py, mesh.triangles), report))
}

/// `asperity analyze`'s results as arrays: normals, curvatures, feature classes, diffusion
/// directions.
#[pyfunction]
fn analyze<'py>(
    py: Python<'py>,
    positions: PyReadonlyArray2<'py, f64>,
    triangles: PyReadonlyArray2<'py, u32>,
    fields: &str,
    repair: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let request: asperity::analysis::AnalysisRequest = from_fields(fields, Spelling::Keyword).map_err(to_py)?;
    let mesh = mesh_of(&positions, &triangles)?;
    let analysis = run(py, false, move || request.analyze(&repaired(mesh, repair)?, Spelling::Keyword))?;
    level::analysis_dict(py, &analysis)
}

/// The 4-k hierarchy of a mesh (`asperity simplify`'s), every level recorded.
#[pyclass(module = "asperity._asperity", frozen)]
struct Hierarchy {
    inner: asperity::hierarchy::Hierarchy,
    /// With `repair`, where the repaired mesh's vertices came from: every array in and out
    /// is in the caller's numbering (#36).
    origins: Option<asperity::mesh::VertexOrigins>,
    /// The caller's vertex count.
    caller_vertices: usize,
}

impl Hierarchy {
    /// The caller's id of the hierarchy's vertex `v`.
    fn caller_id(&self, v: u32) -> u32 {
        self.origins.as_ref().map_or(v, |o| o.source[v as usize])
    }

    /// The hierarchy's vertex that stands for the caller's vertex `u`, if any.
    fn own_id(&self, u: usize) -> Option<u32> {
        match &self.origins {
            Some(o) => o.stands_for[u],
            None => Some(u as u32),
        }
    }

    /// A region given per caller vertex, in the hierarchy's numbering (a split copy is
    /// inside where its original is).
    fn own_region(&self, region: Option<PyReadonlyArray1<'_, bool>>) -> PyResult<Option<Vec<bool>>> {
        let Some(r) = region else { return Ok(None) };
        let n = self.caller_vertices;
        let r = r.as_slice().map_err(|e| InputError::new_err(format!("region: {e}")))?;
        if r.len() != n {
            return Err(InputError::new_err(format!("region has {} values for {n} vertices", r.len())));
        }
        Ok(Some((0..self.inner.positions.len() as u32).map(|v| r[self.caller_id(v) as usize]).collect()))
    }

    /// The base domain, its triangles in the order of `base_triangles` (which
    /// `parametrization`'s face indices count in).
    fn base(&self) -> asperity::hierarchy::LevelMesh {
        asperity::hierarchy::LevelMesh::compact(&self.inner.positions, &self.inner.base_triangles)
    }
}

#[pymethods]
impl Hierarchy {
    /// `fields` is the JSON object of the hierarchy request's fields (the keyword
    /// arguments), read strictly.
    #[new]
    fn new(
        positions: PyReadonlyArray2<'_, f64>,
        triangles: PyReadonlyArray2<'_, u32>,
        fields: &str,
        repair: bool,
        progress: Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let py = positions.py();
        let request: HierarchyRequest = from_fields(fields, Spelling::Keyword).map_err(to_py)?;
        let mesh = mesh_of(&positions, &triangles)?;
        let caller_vertices = mesh.vertex_count();
        let (inner, origins) = run(py, Progress::of(&progress)?, move || {
            let (mesh, origins) = if repair {
                let (mesh, _, origins) = asperity::mesh::repair_with_origins(&mesh)?;
                (mesh, Some(origins))
            } else {
                (mesh, None)
            };
            let options = request.options(mesh.vertex_count(), true, Spelling::Keyword)?;
            let inner = asperity::hierarchy::build(&mesh, &options)?;
            Ok((inner, origins))
        })?;
        Ok(Hierarchy { inner, origins, caller_vertices })
    }

    /// The number of levels, the base domain and the input included.
    #[getter]
    fn levels(&self) -> usize {
        self.inner.levels.len()
    }

    /// Level `l` (0: the base domain; levels − 1: the input): positions, triangles and the
    /// input vertex id of each position.
    #[allow(clippy::type_complexity)]
    fn level<'py>(
        &self,
        py: Python<'py>,
        l: usize,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<u32>>, Bound<'py, PyArray1<u32>>)> {
        let count = self.inner.levels.len();
        if l >= count {
            return Err(InputError::new_err(format!(
                "level {l} is outside the hierarchy's {count} levels (0..{})",
                count - 1
            )));
        }
        let level = if l == 0 { self.base() } else { self.inner.levels[count - 1 - l].clone() };
        let ids: Vec<u32> = level.ids.iter().map(|&v| self.caller_id(v)).collect();
        Ok((
            positions_array(py, level.mesh.positions),
            triangles_array(py, level.mesh.triangles),
            PyArray1::from_vec(py, ids),
        ))
    }

    /// The level at which each of the caller's vertices appears (0 for the base domain's;
    /// −1 for a vertex `repair` dropped because no face used it).
    #[getter]
    fn vertex_level<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let last = (self.inner.levels.len() - 1) as i64;
        let mut own = vec![0i64; self.inner.positions.len()];
        for r in &self.inner.removals {
            own[r.vertex as usize] = last - i64::from(r.step);
        }
        let level: Vec<i64> =
            (0..self.caller_vertices).map(|u| self.own_id(u).map_or(-1, |v| own[v as usize])).collect();
        PyArray1::from_vec(py, level)
    }

    /// The parametrization: for each of the caller's vertices, the index of its base face in
    /// `level(0)`'s triangles and its barycentric coordinates there (a base vertex: a face
    /// it is a corner of, and 1 at that corner); −1 and NaN for a vertex on no face.
    #[allow(clippy::type_complexity)]
    fn parametrization<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyArray1<i64>>, Bound<'py, PyArray2<f64>>)> {
        let points = self.inner.indexed_parametrization().map_err(to_py)?;
        let n = self.caller_vertices;
        let mut face = vec![-1i64; n];
        let mut bary = vec![f64::NAN; 3 * n];
        for u in 0..n {
            if let Some(p) = self.own_id(u).and_then(|v| points[v as usize].as_ref()) {
                face[u] = p.face as i64;
                bary[3 * u..3 * u + 3].copy_from_slice(&p.barycentric);
            }
        }
        let bary = numpy::ndarray::Array2::from_shape_vec((n, 3), bary).expect("n × 3");
        Ok((PyArray1::from_vec(py, face), PyArray2::from_owned_array(py, bary)))
    }

    /// Refines back to full resolution or, with `region` (a boolean per caller vertex), the
    /// library's region refinement (thesis §4.6, the command line's `refine --region`): the
    /// region at the input's resolution, the rest at `base_level`. Positions, triangles, the
    /// caller's id of each vertex, and the report as JSON.
    #[pyo3(signature = (region=None, base_level=0, progress=None))]
    #[allow(clippy::type_complexity)]
    fn refine<'py>(
        &self,
        py: Python<'py>,
        region: Option<PyReadonlyArray1<'py, bool>>,
        base_level: usize,
        progress: Option<Bound<'py, PyAny>>,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<u32>>, Bound<'py, PyArray1<u32>>, String)> {
        let region = self.own_region(region)?;
        let hierarchy = &self.inner;
        let progress = progress.map_or(Ok(Progress::Off), |p| Progress::of(&p))?;
        let (level, report) = run(py, progress, move || match &region {
            None => {
                let mut refiner = asperity::hierarchy::Refiner::new(hierarchy)?;
                let reports = refiner.refine_all()?;
                let report = serde_json::json!({"levels": reports.len(), "base_level": 0});
                Ok((refiner.mesh()?, report))
            }
            Some(inside) => {
                let refined =
                    asperity::hierarchy::region::refine_region(hierarchy, base_level, &|v| inside[v as usize])?;
                let t = refined.totals();
                let report = serde_json::json!({
                    "base_level": base_level,
                    "region_vertices": inside.iter().filter(|&&i| i).count(),
                    "inserted": t.inserted, "relocated": t.relocated, "flips": t.flips,
                    "missing": refined.missing.len(), "rounds": refined.rounds,
                    "self_intersections": refined.self_intersections,
                });
                Ok((refined.mesh, report))
            }
        })?;
        let ids: Vec<u32> = level.ids.iter().map(|&v| self.caller_id(v)).collect();
        Ok((
            positions_array(py, level.mesh.positions),
            triangles_array(py, level.mesh.triangles),
            PyArray1::from_vec(py, ids),
            report.to_string(),
        ))
    }

    /// Refines level by level with `op` called on each level (an `asperity._asperity.Level`,
    /// the base domain first): the operator's exceptions arrive unchanged. With `region` (a
    /// boolean per caller vertex), levels from `base_level` on insert only the region and
    /// the removal rings it needs. Positions, triangles, caller ids and the report as JSON.
    #[pyo3(signature = (op, region=None, base_level=0, progress=None))]
    #[allow(clippy::type_complexity)]
    fn refine_with<'py>(
        &self,
        py: Python<'py>,
        op: Bound<'py, PyAny>,
        region: Option<PyReadonlyArray1<'py, bool>>,
        base_level: usize,
        progress: Option<Bound<'py, PyAny>>,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<u32>>, Bound<'py, PyArray1<u32>>, String)> {
        let own = self.own_region(region)?;
        let region_vertices = own
            .as_ref()
            .map(|own| (0..self.caller_vertices).filter(|&u| self.own_id(u).is_some_and(|v| own[v as usize])).count());
        let wanted =
            own.map(|own| asperity::hierarchy::region::region_with_dependencies(&self.inner, &|v| own[v as usize]));
        let selection = level::Selection { base_level, wanted };
        let progress = progress.map_or(Ok(Progress::Off), |p| Progress::of(&p))?;
        let (refined, reports) =
            level::refine_with_operator(py, &self.inner, &op, &selection, &|v| self.caller_id(v), &progress)?;
        let t = asperity::hierarchy::LevelReport::total(&reports);
        let report = serde_json::json!({
            "levels": reports.len(), "base_level": base_level,
            "region_vertices": region_vertices,
            "with_dependencies": selection.wanted.as_ref().map(|w| w.iter().filter(|&&i| i).count()),
            "inserted": t.inserted, "relocated": t.relocated, "skipped": t.skipped, "flips": t.flips,
            "degree_misses": t.degree_misses,
        });
        let ids: Vec<u32> = refined.ids.iter().map(|&v| self.caller_id(v)).collect();
        Ok((
            positions_array(py, refined.mesh.positions),
            triangles_array(py, refined.mesh.triangles),
            PyArray1::from_vec(py, ids),
            report.to_string(),
        ))
    }

    /// The build's report as JSON: `simplify --json`'s fields (the Hausdorff distance is
    /// measured on this call, with the GIL released).
    fn report(&self, py: Python<'_>) -> PyResult<String> {
        let hierarchy = &self.inner;
        let report = run(py, false, move || {
            let input = Mesh::new(hierarchy.positions.clone(), hierarchy.input_triangles.clone());
            asperity::hierarchy::BuildReport::of(&input, hierarchy, &hierarchy.base_mesh().mesh)
        })?;
        Ok(serde_json::to_string(&report).expect("a report serialises"))
    }

    /// Build time by stage, as JSON.
    fn stages(&self) -> String {
        serde_json::to_string(&self.inner.stages).expect("stages serialise")
    }

    /// The number of the caller's vertices.
    #[getter]
    fn input_vertices(&self) -> usize {
        self.caller_vertices
    }
}

/// `asperity detail`: the refined mesh (positions, triangles, the recipe's vertex colours
/// when it has a `[color]` table) and the report as JSON.
#[pyfunction]
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
fn detail<'py>(
    py: Python<'py>,
    positions: PyReadonlyArray2<'py, f64>,
    triangles: PyReadonlyArray2<'py, u32>,
    recipe: &str,
    recipe_is_json: bool,
    fields: &str,
    allow_self_intersections: bool,
    repair: bool,
    progress: Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<u32>>, Option<Bound<'py, PyArray2<u8>>>, String)> {
    let request: HierarchyRequest = from_fields(fields, Spelling::Keyword).map_err(to_py)?;
    // A recipe given as a dict arrives as JSON and is read as the TOML it stands for.
    let text = if recipe_is_json {
        let value: serde_json::Value =
            serde_json::from_str(recipe).map_err(|e| InputError::new_err(format!("recipe: {e}")))?;
        toml::to_string(&value).map_err(|e| InputError::new_err(format!("recipe: {e}")))?
    } else {
        recipe.to_string()
    };
    let recipe = asperity::detail::Recipe::parse(&text).map_err(|(line, message)| {
        InputError::new_err(match line {
            Some(line) => format!("recipe: line {line}: {message}"),
            None => format!("recipe: {message}"),
        })
    })?;
    let mesh = mesh_of(&positions, &triangles)?;
    let (mesh, report) = run(py, Progress::of(&progress)?, move || {
        let mesh = repaired(mesh, repair)?;
        // The recipe's [hierarchy] table under the keyword arguments, as the command line's
        // `detail` applies it under its flags.
        let simplify = request.options_over(&recipe.hierarchy, mesh.vertex_count(), false, Spelling::Keyword)?;
        let options =
            DetailOptions { simplify, no_self_intersections: !allow_self_intersections, ..Default::default() };
        let outcome = asperity::detail::apply(&mesh, &recipe, &options)?;
        let report = serde_json::json!({
            "input_vertices": mesh.vertex_count(),
            "base_vertices": outcome.base_vertices,
            "output_vertices": outcome.result.mesh.vertex_count(),
            "levels": outcome.levels,
            "steps": outcome.steps,
            "self_intersections": outcome.intersections,
            "seconds": { "hierarchy": outcome.seconds.hierarchy, "detail": outcome.seconds.detail, "refine": outcome.seconds.refine },
        });
        Ok((outcome.result.mesh, report))
    })?;
    let colors = mesh.colors.map(|c| arrays::colors_array(py, c));
    Ok((positions_array(py, mesh.positions), triangles_array(py, mesh.triangles), colors, report.to_string()))
}

/// The symmetric Hausdorff distance between two meshes (CGAL), as a share of the first's
/// bounding-box diagonal: what `simplify` and `compare` report.
#[pyfunction]
fn hausdorff(
    py: Python<'_>,
    reference_positions: PyReadonlyArray2<'_, f64>,
    reference_triangles: PyReadonlyArray2<'_, u32>,
    other_positions: PyReadonlyArray2<'_, f64>,
    other_triangles: PyReadonlyArray2<'_, u32>,
) -> PyResult<f64> {
    let reference = mesh_of(&reference_positions, &reference_triangles)?;
    let other = mesh_of(&other_positions, &other_triangles)?;
    run(py, false, move || asperity::hierarchy::compare::relative_hausdorff(&reference, &other))
}

/// `asperity compare`'s report (both tables), as JSON.
#[pyfunction]
fn compare(
    py: Python<'_>,
    positions: PyReadonlyArray2<'_, f64>,
    triangles: PyReadonlyArray2<'_, u32>,
    fields: &str,
    repair: bool,
    progress: Bound<'_, PyAny>,
) -> PyResult<String> {
    let request: asperity::hierarchy::CompareRequest = from_fields(fields, Spelling::Keyword).map_err(to_py)?;
    let mesh = mesh_of(&positions, &triangles)?;
    let report =
        run(py, Progress::of(&progress)?, move || request.report(&repaired(mesh, repair)?, Spelling::Keyword))?;
    Ok(serde_json::to_string(&report).expect("the report serialises"))
}

/// `asperity terrain`'s heights as a rows × columns array.
#[pyfunction]
fn terrain<'py>(py: Python<'py>, fields: &str, progress: Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (request, tile) = TerrainRequest::from_fields(fields, Spelling::Keyword).map_err(to_py)?;
    let field = run(py, Progress::of(&progress)?, move || request.heights(tile, Spelling::Keyword))?;
    Ok(heights_array(py, field))
}

/// `asperity terrain --erode hydraulic --layers …`'s heights and layers as rows × columns
/// arrays: the heights, then (name, mask) per layer.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn terrain_layers<'py>(
    py: Python<'py>,
    fields: &str,
    progress: Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Vec<(String, Bound<'py, PyArray2<f64>>)>)> {
    let (request, tile) = TerrainRequest::from_fields(fields, Spelling::Keyword).map_err(to_py)?;
    let (heights, layers) =
        run(py, Progress::of(&progress)?, move || request.heights_and_layers(tile, Spelling::Keyword))?;
    let layers =
        layers.into_iter().map(|(layer, field)| (layer.name().to_string(), heights_array(py, field))).collect();
    Ok((heights_array(py, heights), layers))
}

/// `asperity terrain`'s mesh (a heightfield's, or the dual method's surface): positions,
/// triangles, normals and colours.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn terrain_mesh<'py>(
    py: Python<'py>,
    fields: &str,
) -> PyResult<(
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<u32>>,
    Option<Bound<'py, PyArray2<f64>>>,
    Option<Bound<'py, PyArray2<u8>>>,
)> {
    let (request, tile) = TerrainRequest::from_fields(fields, Spelling::Keyword).map_err(to_py)?;
    let mesh = run(py, false, move || request.mesh(tile, Spelling::Keyword))?;
    let normals = mesh.normals.map(|n| vectors_array(py, n));
    let colors = mesh.colors.map(|c| arrays::colors_array(py, c));
    Ok((positions_array(py, mesh.positions), triangles_array(py, mesh.triangles), normals, colors))
}

/// `asperity noise`'s field at given points: 2D points (n, 2) sample the plane as the
/// images do; 3D points (n, 3) sample space with the global frame. `fields` is the JSON
/// object of the request's fields (the keyword arguments), read strictly.
#[pyfunction]
fn noise<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    fields: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let request: NoiseRequest = from_fields(fields, Spelling::Keyword).map_err(to_py)?;
    let (dimension, points) = points_of(&points)?;
    let values = run(py, false, move || request.values_at(&points, dimension == 2, Spelling::Keyword))?;
    Ok(PyArray1::from_vec(py, values))
}

/// `asperity render`'s picture as a height × width × 4 RGBA array.
#[pyfunction]
fn render<'py>(
    py: Python<'py>,
    positions: PyReadonlyArray2<'py, f64>,
    triangles: PyReadonlyArray2<'py, u32>,
    fields: &str,
    repair: bool,
) -> PyResult<Bound<'py, PyArray3<u8>>> {
    let request: asperity::render::RenderRequest = from_fields(fields, Spelling::Keyword).map_err(to_py)?;
    let mesh = mesh_of(&positions, &triangles)?;
    let picture = run(py, false, move || {
        asperity::render::render(&repaired(mesh, repair)?, &request.options(Spelling::Keyword)?)
    })?;
    let array =
        numpy::ndarray::Array3::from_shape_vec((picture.height, picture.width, 4), picture.rgba).expect("h × w × 4");
    Ok(numpy::PyArray3::from_owned_array(py, array))
}

/// `asperity clouds`' picture as an RGB array, and the sky's cloud cover.
#[pyfunction]
fn clouds<'py>(py: Python<'py>, fields: &str) -> PyResult<(Bound<'py, PyArray3<u8>>, f64)> {
    let request: asperity::terrain::CloudRequest = from_fields(fields, Spelling::Keyword).map_err(to_py)?;
    let side = request.size as usize;
    let (rgb, cover) = run(py, false, move || request.picture(Spelling::Keyword))?;
    let array = numpy::ndarray::Array3::from_shape_vec((side, side, 3), rgb)
        .map_err(|e| InternalError::new_err(e.to_string()))?;
    Ok((numpy::PyArray3::from_owned_array(py, array), cover))
}

#[pymodule]
fn _asperity(m: &Bound<'_, PyModule>) -> PyResult<()> {
    interrupt::quiet_cancellation_panics();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("InputError", m.py().get_type::<InputError>())?;
    m.add("InternalError", m.py().get_type::<InternalError>())?;
    m.add("Cancelled", m.py().get_type::<Cancelled>())?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(write, m)?)?;
    m.add_function(wrap_pyfunction!(info, m)?)?;
    m.add_function(wrap_pyfunction!(repair, m)?)?;
    m.add_function(wrap_pyfunction!(analyze, m)?)?;
    m.add_function(wrap_pyfunction!(detail, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(hausdorff, m)?)?;
    m.add_function(wrap_pyfunction!(terrain, m)?)?;
    m.add_function(wrap_pyfunction!(terrain_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(terrain_layers, m)?)?;
    m.add_function(wrap_pyfunction!(noise, m)?)?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(clouds, m)?)?;
    m.add_class::<Hierarchy>()?;
    m.add_class::<level::Level>()?;
    Ok(())
}
