//! Texture coordinates and materials carried by a mesh (#22 B).
//!
//! UVs are held per triangle corner, as OBJ holds them (`f v/vt`): vertices stay welded by
//! position, so the hierarchy and the operators see the surface's real topology, and a
//! vertex on a seam has one UV per side. A **seam** edge is one whose two faces disagree on
//! the UV (by value) of either end, or on the material. Formats that hold one UV per vertex
//! (PLY, glTF) read into corners indexed by vertex and are written split: one vertex per
//! distinct (vertex, UV) ([`split_by_uv`]).

use std::collections::HashMap;

use glam::DVec3;

use super::Mesh;
use crate::error::{Error, Result};

/// Texture coordinates per triangle corner: `values[corners[f][k]]` is corner k of face f.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CornerUvs {
    /// The distinct coordinates (u, v).
    pub values: Vec<[f64; 2]>,
    /// Per triangle, the index of each corner's coordinates.
    pub corners: Vec<[u32; 3]>,
}

/// Materials named per face, and the libraries that define them (OBJ `mtllib`/`usemtl`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Materials {
    /// Material library files, as the input names them.
    pub libraries: Vec<String>,
    /// Material names.
    pub names: Vec<String>,
    /// Per triangle, an index into `names`, or `u32::MAX` for a face before any `usemtl`.
    pub faces: Vec<u32>,
}

impl CornerUvs {
    /// One UV per vertex (PLY, glTF): corners index the values by vertex.
    pub fn per_vertex(values: Vec<[f64; 2]>, triangles: &[[u32; 3]]) -> Self {
        CornerUvs { values, corners: triangles.to_vec() }
    }

    /// The UV of corner `k` of face `f`.
    pub fn at(&self, f: usize, k: usize) -> [f64; 2] {
        self.values[self.corners[f][k] as usize]
    }

    /// Checks the arrays against a mesh of `faces` triangles.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the first inconsistency.
    pub fn check(&self, faces: usize) -> Result<()> {
        if self.corners.len() != faces {
            return Err(Error::InvalidInput(format!("UVs are given for {} of {faces} faces", self.corners.len())));
        }
        if let Some(i) = self.values.iter().position(|uv| !(uv[0].is_finite() && uv[1].is_finite())) {
            return Err(Error::InvalidInput(format!("texture coordinate {i} is not finite")));
        }
        let n = self.values.len();
        for (f, c) in self.corners.iter().enumerate() {
            if let Some(i) = c.iter().find(|&&i| i as usize >= n) {
                return Err(Error::InvalidInput(format!("face {f} names texture coordinate {i} of {n}")));
            }
        }
        Ok(())
    }
}

/// Bit pattern of a UV, for comparing by value (−0 and 0 differ: a file that wrote both
/// meant two coordinates).
fn bits(uv: [f64; 2]) -> [u64; 2] {
    [uv[0].to_bits(), uv[1].to_bits()]
}

/// The seam edges of a mesh (smaller id first, sorted): interior edges whose two faces
/// disagree on an end's UV (by value) or on the material. Empty without UVs or materials.
pub fn seam_edges(mesh: &Mesh) -> Vec<[u32; 2]> {
    if mesh.uvs.is_none() && mesh.materials.is_none() {
        return Vec::new();
    }
    // Directed edge → (face, corner of its start).
    let mut half: HashMap<[u32; 2], (usize, usize)> = HashMap::with_capacity(3 * mesh.triangles.len());
    for (f, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            half.insert([t[k], t[(k + 1) % 3]], (f, k));
        }
    }
    let uv_of = |f: usize, k: usize| mesh.uvs.as_ref().map(|u| bits(u.at(f, k)));
    let material_of = |f: usize| mesh.materials.as_ref().map(|m| m.faces[f]);
    let mut seams: Vec<[u32; 2]> = half
        .iter()
        .filter(|([a, b], _)| a < b)
        .filter_map(|(&[a, b], &(f, k))| {
            let &(g, j) = half.get(&[b, a])?;
            // In f, a is corner k and b corner k+1; in g, b is corner j and a corner j+1.
            let differs = uv_of(f, k) != uv_of(g, (j + 1) % 3)
                || uv_of(f, (k + 1) % 3) != uv_of(g, j)
                || material_of(f) != material_of(g);
            differs.then_some([a, b])
        })
        .collect();
    seams.sort_unstable();
    seams
}

/// The mesh with one vertex per distinct (vertex, UV) and the UVs per vertex (corners
/// indexing values by vertex), for formats that hold one UV per vertex. Each vertex keeps
/// its id for the first UV its faces give it; further UVs get copies after the last vertex,
/// with the normals, colours and scalars of the vertex they copy (a mesh whose vertices
/// each have one UV keeps its vertices in order). Vertices on no face get UV (0, 0). The
/// second value maps each vertex of the result to the vertex it copies.
pub fn split_by_uv(mesh: &Mesh) -> (Mesh, Vec<u32>) {
    let n = mesh.vertex_count();
    let Some(uvs) = &mesh.uvs else { return (mesh.clone(), (0..n as u32).collect()) };
    let mut source: Vec<u32> = (0..n as u32).collect();
    let mut values: Vec<[f64; 2]> = vec![[0.0, 0.0]; n];
    let mut first: Vec<Option<[u64; 2]>> = vec![None; n];
    let mut copies: HashMap<(u32, [u64; 2]), u32> = HashMap::new();
    let mut triangles = Vec::with_capacity(mesh.triangles.len());
    for (f, t) in mesh.triangles.iter().enumerate() {
        let mut out = [0u32; 3];
        for k in 0..3 {
            let (v, uv) = (t[k], uvs.at(f, k));
            out[k] = match first[v as usize] {
                None => {
                    first[v as usize] = Some(bits(uv));
                    values[v as usize] = uv;
                    v
                }
                Some(b) if b == bits(uv) => v,
                Some(_) => *copies.entry((v, bits(uv))).or_insert_with(|| {
                    source.push(v);
                    values.push(uv);
                    (source.len() - 1) as u32
                }),
            };
        }
        triangles.push(out);
    }
    let pick = |v: &[DVec3]| source.iter().map(|&s| v[s as usize]).collect::<Vec<_>>();
    let split = Mesh {
        positions: pick(&mesh.positions),
        normals: mesh.normals.as_deref().map(pick),
        colors: mesh.colors.as_ref().map(|c| source.iter().map(|&s| c[s as usize]).collect()),
        scalars: mesh
            .scalars
            .iter()
            .map(|(name, v)| (name.clone(), source.iter().map(|&s| v[s as usize]).collect()))
            .collect(),
        uvs: Some(CornerUvs::per_vertex(values, &triangles)),
        materials: mesh.materials.clone(),
        triangles,
    };
    (split, source)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles sharing edge 1–2; the second gives vertex 2 another UV.
    fn two_faces(seam: bool) -> Mesh {
        let mut mesh = Mesh::new(
            vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE],
            vec![[0, 1, 2], [2, 1, 3]],
        );
        let second = if seam { 4 } else { 2 };
        mesh.uvs = Some(CornerUvs {
            values: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [0.5, 1.0]],
            corners: vec![[0, 1, 2], [second, 1, 3]],
        });
        mesh
    }

    #[test]
    fn a_seam_is_an_edge_whose_faces_disagree_on_a_uv() {
        assert!(seam_edges(&two_faces(false)).is_empty());
        assert_eq!(seam_edges(&two_faces(true)), vec![[1, 2]]);
    }

    #[test]
    fn splitting_by_uv_gives_one_vertex_per_distinct_pair() {
        let (split, source) = split_by_uv(&two_faces(true));
        assert_eq!(split.vertex_count(), 5);
        assert_eq!(source, vec![0, 1, 2, 3, 2]);
        // One UV per vertex: each corner reads its vertex's (checked corner by corner below).
        let (same, identity) = split_by_uv(&two_faces(false));
        assert_eq!((same.positions, identity), (two_faces(false).positions, vec![0, 1, 2, 3]));
        let uvs = split.uvs.as_ref().unwrap();
        for (f, t) in split.triangles.iter().enumerate() {
            for k in 0..3 {
                assert_eq!(uvs.at(f, k), uvs.values[t[k] as usize]);
                assert_eq!(split.positions[t[k] as usize], two_faces(true).positions[source[t[k] as usize] as usize]);
            }
        }
        split.check().unwrap();
    }
}
