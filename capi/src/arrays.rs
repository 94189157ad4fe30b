//! Flat arrays to and from the library's types.

use asperity::analysis::SurfaceAnalysis;
use asperity::hierarchy::LevelMesh;
use asperity::mesh::uv::CornerUvs;
use asperity::{Error, Mesh, Result};
use glam::DVec3;

use crate::bridge::{Analysis, LevelArrays, MeshArrays};

/// A mesh from x y z per vertex and three ids per triangle, checked.
pub fn mesh_of(positions: &[f64], triangles: &[u32]) -> Result<Mesh> {
    if !positions.len().is_multiple_of(3) || !triangles.len().is_multiple_of(3) {
        return Err(Error::InvalidInput(format!(
            "{} coordinates and {} triangle ids are not multiples of 3",
            positions.len(),
            triangles.len()
        )));
    }
    let mesh = Mesh::new(vectors_of(positions), triangles.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect());
    mesh.check()?;
    Ok(mesh)
}

/// Vectors from x y z triples (the length is a multiple of 3).
pub fn vectors_of(flat: &[f64]) -> Vec<DVec3> {
    flat.chunks_exact(3).map(|p| DVec3::new(p[0], p[1], p[2])).collect()
}

/// x y z triples.
pub fn flat(vectors: &[DVec3]) -> Vec<f64> {
    vectors.iter().flat_map(|p| [p.x, p.y, p.z]).collect()
}

/// The mesh as flat arrays.
pub fn arrays_of(mesh: &Mesh) -> MeshArrays {
    MeshArrays { positions: flat(&mesh.positions), triangles: mesh.triangles.iter().flatten().copied().collect() }
}

/// A level's mesh, ids and corner UVs as flat arrays.
pub fn level_arrays(level: &LevelMesh) -> LevelArrays {
    let corner_uvs = match &level.mesh.uvs {
        Some(uvs) => (0..level.mesh.face_count()).flat_map(|f| (0..3).flat_map(move |k| uvs.at(f, k))).collect(),
        None => Vec::new(),
    };
    LevelArrays { mesh: arrays_of(&level.mesh), ids: level.ids.clone(), corner_uvs }
}

/// UVs from u v per face corner (6 per triangle; empty: none).
pub fn corner_uvs_of(flat: &[f64], faces: usize) -> Result<Option<CornerUvs>> {
    if flat.is_empty() {
        return Ok(None);
    }
    if flat.len() != 6 * faces {
        return Err(Error::InvalidInput(format!("{} texture coordinates for {faces} triangles (6 each)", flat.len())));
    }
    let values = flat.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
    let corners = (0..faces as u32).map(|f| [3 * f, 3 * f + 1, 3 * f + 2]).collect();
    let uvs = CornerUvs { values, corners };
    uvs.check(faces)?;
    Ok(Some(uvs))
}

/// An analysis as flat arrays.
pub fn analysis_arrays(analysis: &SurfaceAnalysis) -> Analysis {
    let c = &analysis.curvatures;
    Analysis {
        normals: flat(&analysis.normals),
        mean_curvature: c.mean.clone(),
        gaussian_curvature: c.gaussian.clone(),
        k1: c.k1.clone(),
        k2: c.k2.clone(),
        feature_class: analysis.classes.iter().map(|&k| k as u8).collect(),
    }
}

/// One flag per input vertex from a byte mask (empty: none given).
pub fn mask_of(inside: &[u8], vertices: usize) -> Result<Vec<bool>> {
    if inside.len() != vertices {
        return Err(Error::InvalidInput(format!("the selection has {} values for {vertices} vertices", inside.len())));
    }
    Ok(inside.iter().map(|&b| b != 0).collect())
}
