//! The reference decimators `asperity compare` runs beside the hierarchy: OpenMesh's
//! quadric decimater and CGAL's edge collapse.

use super::{flat_positions, sys, unflatten_positions};
use crate::error::Result;
use crate::mesh::Mesh;

/// OpenMesh's `DecimaterT` with `ModQuadricT` down to `target_vertices` (a reference for
/// `asperity compare`).
///
/// # Errors
/// [`Error::InvalidInput`](crate::Error::InvalidInput) for an inconsistent mesh; [`Error::Native`](crate::Error::Native) when OpenMesh refuses it.
pub fn openmesh_decimate(mesh: &Mesh, target_vertices: usize) -> Result<Mesh> {
    mesh.check()?;
    let d = sys::openmesh_decimate(flat_positions(&mesh.positions), mesh.triangles.as_flattened(), target_vertices)?;
    Ok(decimated(d))
}

/// CGAL's `edge_collapse` with `GarlandHeckbert_plane_policies`, stopping at the edge count
/// of a `target_vertices`-vertex surface of the input's topology (a reference for
/// `asperity compare`).
///
/// # Errors
/// [`Error::InvalidInput`](crate::Error::InvalidInput) for an inconsistent mesh; [`Error::Native`](crate::Error::Native) when CGAL refuses it.
pub fn cgal_decimate(mesh: &Mesh, target_vertices: usize) -> Result<Mesh> {
    mesh.check()?;
    let d = sys::cgal_decimate(flat_positions(&mesh.positions), mesh.triangles.as_flattened(), target_vertices)?;
    Ok(decimated(d))
}

fn decimated(d: sys::DecimatedMesh) -> Mesh {
    Mesh::new(unflatten_positions(&d.positions), d.triangles.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect())
}
