//! Discrete gradient of a piecewise-linear per-vertex function (thesis eq. 3.3, in the form
//! of Botsch et al. 2010 eq. 3.9 — the thesis prints the second edge as xⱼ − xₖ, which is
//! not exact for linear functions; xⱼ − xᵢ is).

use glam::DVec3;
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// The gradient of `values` (one per vertex) on every face: constant per triangle,
/// ∇f = (fⱼ − fᵢ)(xᵢ − xₖ)^⊥ / 2A + (fₖ − fᵢ)(xⱼ − xᵢ)^⊥ / 2A, with ⊥ the rotation by 90°
/// in the face plane (n × ·). Zero on degenerate faces.
///
/// # Errors
/// [`Error::InvalidInput`] when there is not one value per vertex.
pub fn face_gradients(mesh: &Mesh, values: &[f64]) -> Result<Vec<DVec3>> {
    if values.len() != mesh.positions.len() {
        return Err(Error::InvalidInput(format!("{} values for {} vertices", values.len(), mesh.positions.len())));
    }
    Ok((0..mesh.triangles.len())
        .into_par_iter()
        .map(|f| {
            let [i, j, k] = mesh.triangles[f].map(|v| v as usize);
            let [xi, xj, xk] = mesh.triangle_points(f);
            let cross = (xj - xi).cross(xk - xi);
            let twice_area = cross.length();
            if twice_area <= 0.0 {
                return DVec3::ZERO;
            }
            let n = cross / twice_area;
            ((values[j] - values[i]) * n.cross(xi - xk) + (values[k] - values[i]) * n.cross(xj - xi)) / twice_area
        })
        .collect())
}
