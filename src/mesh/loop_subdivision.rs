//! Loop subdivision (C. Loop, "Smooth Subdivision Surfaces Based on Triangles", MSc thesis,
//! University of Utah, 1987; the boundary rules of Hoppe et al., SIGGRAPH 1994): every
//! triangle becomes four, new edge points are 3/8 (a + b) + 1/8 (c + d), old vertices move
//! to (1 − nβ) v + β Σ neighbours with β = (5/8 − (3/8 + 1/4 cos 2π/n)²) / n; on a
//! boundary, edge points are midpoints and vertices 3/4 v + 1/8 (b₀ + b₁).
//! Used to make large test inputs from the shared meshes; attributes are not carried.

use glam::DVec3;
use rayon::prelude::*;

use super::Mesh;
use super::validate::EdgeTable;
use crate::error::{Error, Result};

/// One Loop subdivision step of a manifold triangle mesh: 4× the faces; the old vertices
/// keep their ids, the edge points follow in edge order (sorted by vertex ids).
///
/// # Errors
/// [`Error::Topology`] for a non-manifold edge or a face repeating a vertex.
pub fn loop_subdivide(mesh: &Mesh) -> Result<Mesh> {
    mesh.check()?;
    let table = EdgeTable::build(&mesh.triangles);
    let n = mesh.vertex_count();
    let p = &mesh.positions;

    // Edge points, and for each old vertex the sums its rule needs.
    let mut edge_points = Vec::new();
    let mut neighbour_sum = vec![DVec3::ZERO; n];
    let mut valence = vec![0u32; n];
    let mut boundary_sum = vec![DVec3::ZERO; n];
    let mut boundary_edges = vec![0u32; n];
    let mut face_edges = vec![[u32::MAX; 3]; mesh.face_count()];
    for group in table.groups() {
        let (a, b) = (group[0].lo as usize, group[0].hi as usize);
        let id = (n + edge_points.len()) as u32;
        let point = match group {
            [_] => {
                boundary_sum[a] += p[b];
                boundary_sum[b] += p[a];
                boundary_edges[a] += 1;
                boundary_edges[b] += 1;
                0.5 * (p[a] + p[b])
            }
            [u, w] => {
                let opposite = |face: u32| {
                    let t = mesh.triangles[face as usize];
                    p[t.iter().find(|&&v| v as usize != a && v as usize != b).copied().expect("a third vertex")
                        as usize]
                };
                0.375 * (p[a] + p[b]) + 0.125 * (opposite(u.face) + opposite(w.face))
            }
            _ => {
                return Err(Error::Topology {
                    msg: format!("Loop subdivision: edge {a}–{b} has {} faces (repair the mesh first)", group.len()),
                    faces: group.iter().map(|u| crate::mesh::FaceId(u.face)).collect(),
                });
            }
        };
        neighbour_sum[a] += p[b];
        neighbour_sum[b] += p[a];
        valence[a] += 1;
        valence[b] += 1;
        for u in group {
            let t = mesh.triangles[u.face as usize];
            let k = (0..3).find(|&k| t[k].min(t[(k + 1) % 3]) == u.lo && t[k].max(t[(k + 1) % 3]) == u.hi);
            face_edges[u.face as usize][k.expect("the edge is a side of its face")] = id;
        }
        edge_points.push(point);
    }
    if let Some(f) = face_edges.iter().position(|e| e.contains(&u32::MAX)) {
        return Err(Error::Topology {
            msg: format!("Loop subdivision: face {f} repeats a vertex (repair the mesh first)"),
            faces: vec![crate::mesh::FaceId(f as u32)],
        });
    }

    let moved: Vec<DVec3> = (0..n)
        .into_par_iter()
        .map(|v| match (boundary_edges[v], valence[v]) {
            (0, 0) => p[v],
            (0, k) => {
                let k = f64::from(k);
                let c = 0.375 + 0.25 * (std::f64::consts::TAU / k).cos();
                let beta = (0.625 - c * c) / k;
                (1.0 - k * beta) * p[v] + beta * neighbour_sum[v]
            }
            // A regular boundary vertex; corners of non-manifold boundary fans stay put.
            (2, _) => 0.75 * p[v] + 0.125 * boundary_sum[v],
            _ => p[v],
        })
        .collect();

    let mut positions = moved;
    positions.extend(edge_points);
    let triangles = mesh
        .triangles
        .iter()
        .zip(&face_edges)
        .flat_map(|(&[a, b, c], &[ab, bc, ca])| [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]])
        .collect();
    Ok(Mesh::new(positions, triangles))
}
