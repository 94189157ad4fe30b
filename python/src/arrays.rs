//! numpy arrays ↔ the crate's meshes: positions (n, 3) float64, triangles (m, 3) uint32,
//! vectors (n, 3) float64, colours (n, 3) uint8. Arrays handed to Python take over the
//! Rust buffers (no copy); arrays read from Python are checked for shape, finiteness and
//! index range with messages naming the element.

use glam::DVec3;
use numpy::ndarray::Array2;
use numpy::{PyArray2, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::InputError;
use asperity::mesh::{Mesh, Rgb};

/// The rows of an (n, k) array as a flat slice, after checking its shape.
fn rows<'a, T: numpy::Element>(array: &'a PyReadonlyArray2<'_, T>, columns: usize, what: &str) -> PyResult<&'a [T]> {
    let shape = array.shape();
    if shape[1] != columns {
        return Err(InputError::new_err(format!("{what} must be an (n, {columns}) array, not {shape:?}")));
    }
    array.as_slice().map_err(|e| InputError::new_err(format!("{what}: {e}")))
}

/// Positions from an (n, 3) float64 array.
pub fn positions_of(array: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<DVec3>> {
    vectors(rows(array, 3, "positions")?, "position")
}

fn vectors(flat: &[f64], what: &str) -> PyResult<Vec<DVec3>> {
    let out: Vec<DVec3> = flat.chunks_exact(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect();
    if let Some(k) = out.iter().position(|p| !p.is_finite()) {
        return Err(InputError::new_err(format!("{what} {k} is not finite: {:?}", out[k].to_array())));
    }
    Ok(out)
}

/// Per-vertex vectors (normals) from an (n, 3) float64 array of `n` rows.
pub fn vectors_of(array: &PyReadonlyArray2<'_, f64>, n: usize, what: &str) -> PyResult<Vec<DVec3>> {
    let out = vectors(rows(array, 3, what)?, what)?;
    if out.len() != n {
        return Err(InputError::new_err(format!("{what} has {} rows for {n} vertices", out.len())));
    }
    Ok(out)
}

/// Colours from an (n, 3) uint8 array of `n` rows.
pub fn colors_of(array: &PyReadonlyArray2<'_, u8>, n: usize) -> PyResult<Vec<Rgb>> {
    let flat = rows(array, 3, "colors")?;
    if flat.len() != 3 * n {
        return Err(InputError::new_err(format!("colors has {} rows for {n} vertices", flat.len() / 3)));
    }
    Ok(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// A mesh from positions and triangles, every index checked.
pub fn mesh_of(positions: &PyReadonlyArray2<'_, f64>, triangles: &PyReadonlyArray2<'_, u32>) -> PyResult<Mesh> {
    let positions = positions_of(positions)?;
    let flat = rows(triangles, 3, "triangles")?;
    let n = positions.len();
    if let Some(k) = flat.iter().position(|&v| v as usize >= n) {
        return Err(InputError::new_err(format!(
            "triangle {} names vertex {}, outside the {n} positions",
            k / 3,
            flat[k]
        )));
    }
    let triangles = flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    Ok(Mesh::new(positions, triangles))
}

/// 2D or 3D points from an (n, 2) or (n, 3) float64 array: the dimension and the points
/// (z = 0 for 2D).
pub fn points_of(array: &PyReadonlyArray2<'_, f64>) -> PyResult<(usize, Vec<DVec3>)> {
    let columns = array.shape()[1];
    let flat = match columns {
        2 | 3 => rows(array, columns, "points")?,
        _ => return Err(InputError::new_err(format!("points must be (n, 2) or (n, 3), not {:?}", array.shape()))),
    };
    let points: Vec<DVec3> =
        flat.chunks_exact(columns).map(|c| DVec3::new(c[0], c[1], if columns == 3 { c[2] } else { 0.0 })).collect();
    if let Some(k) = points.iter().position(|p| !p.is_finite()) {
        return Err(InputError::new_err(format!("point {k} is not finite")));
    }
    Ok((columns, points))
}

/// An (n, 3) float64 array taking over `vectors`' buffer.
pub fn vectors_array(py: Python<'_>, vectors: Vec<DVec3>) -> Bound<'_, PyArray2<f64>> {
    let n = vectors.len();
    let flat: Vec<f64> = match bytemuck::allocation::try_cast_vec::<DVec3, f64>(vectors) {
        Ok(flat) => flat,
        Err((_, vectors)) => vectors.iter().flat_map(|v| v.to_array()).collect(),
    };
    PyArray2::from_owned_array(py, Array2::from_shape_vec((n, 3), flat).expect("n × 3"))
}

/// Positions as an (n, 3) float64 array.
pub fn positions_array(py: Python<'_>, positions: Vec<DVec3>) -> Bound<'_, PyArray2<f64>> {
    vectors_array(py, positions)
}

/// Triangles as an (m, 3) uint32 array.
pub fn triangles_array(py: Python<'_>, triangles: Vec<[u32; 3]>) -> Bound<'_, PyArray2<u32>> {
    let m = triangles.len();
    let flat: Vec<u32> = triangles.into_iter().flatten().collect();
    PyArray2::from_owned_array(py, Array2::from_shape_vec((m, 3), flat).expect("m × 3"))
}

/// Colours as an (n, 3) uint8 array.
pub fn colors_array(py: Python<'_>, colors: Vec<Rgb>) -> Bound<'_, PyArray2<u8>> {
    let n = colors.len();
    let flat: Vec<u8> = colors.into_iter().flatten().collect();
    PyArray2::from_owned_array(py, Array2::from_shape_vec((n, 3), flat).expect("n × 3"))
}

/// A terrain's heights as a (rows, columns) float64 array taking over their buffer.
pub fn heights_array(py: Python<'_>, field: asperity::terrain::Heightfield) -> Bound<'_, PyArray2<f64>> {
    let shape = (field.rect.height(), field.rect.width());
    PyArray2::from_owned_array(py, Array2::from_shape_vec(shape, field.heights).expect("rows × columns"))
}
