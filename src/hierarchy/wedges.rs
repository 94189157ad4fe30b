//! Texture coordinates and materials on every level (#22 B): which of a seam vertex's UVs
//! a level's face takes.
//!
//! Levels keep the input's vertices, so a face's corner takes its vertex's UV, and a vertex
//! off the seams has one. A seam vertex has one UV per *wedge*, the sector of its faces
//! between two seam edges. Seams are simplified along themselves ([`super::lines`]), so a
//! level's seam edge v–x stands for the input's seam path from v to x, and a level's face
//! at v lies in the wedge that starts at the first input edge of the seam path bounding
//! its sector. Turning clockwise around v from the face until a seam edge v–x, then
//! following the input seam from v towards x, finds that first edge v–n; the wedge is the
//! input face on the left of v → n. A boundary met first is passed by turning the other
//! way (the wedge is then on the right of the seam edge found).

use rustc_hash::FxHashMap;

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::mesh::uv::{CornerUvs, Materials, seam_edges};

/// The input's corner UVs and materials, and what finding wedges needs.
#[derive(Debug, Clone)]
pub struct Wedges {
    uvs: Option<CornerUvs>,
    materials: Option<Materials>,
    /// Directed input edge → (face on its left, corner of its start).
    half: FxHashMap<[u32; 2], (u32, u8)>,
    /// Seam neighbours of each vertex (empty off the seams).
    seam_neighbours: Vec<Vec<u32>>,
    /// A face and corner of each vertex, for vertices off the seams.
    any_corner: Vec<(u32, u8)>,
    /// The input's triangles.
    triangles: Vec<[u32; 3]>,
}

impl Wedges {
    /// The wedges of `input`; `None` when it has neither UVs nor materials.
    pub fn of(input: &Mesh) -> Option<Self> {
        if input.uvs.is_none() && input.materials.is_none() {
            return None;
        }
        let n = input.vertex_count();
        let mut half = FxHashMap::default();
        let mut any_corner = vec![(u32::MAX, 0u8); n];
        for (f, t) in input.triangles.iter().enumerate() {
            for k in 0..3 {
                half.insert([t[k], t[(k + 1) % 3]], (f as u32, k as u8));
                any_corner[t[k] as usize] = (f as u32, k as u8);
            }
        }
        let mut seam_neighbours = vec![Vec::new(); n];
        for [a, b] in seam_edges(input) {
            seam_neighbours[a as usize].push(b);
            seam_neighbours[b as usize].push(a);
        }
        Some(Wedges {
            uvs: input.uvs.clone(),
            materials: input.materials.clone(),
            half,
            seam_neighbours,
            any_corner,
            triangles: input.triangles.clone(),
        })
    }

    /// The corner UVs and face materials of a level's faces (input ids; every vertex an
    /// input vertex), in `triangles`' order.
    ///
    /// # Errors
    /// [`Error::Internal`] when a face's wedge cannot be found (a seam the level does not
    /// keep: a bug of the simplification).
    pub fn level(&self, triangles: &[[u32; 3]]) -> Result<(Option<CornerUvs>, Option<Materials>)> {
        let n = self.seam_neighbours.len();
        if let Some(v) = triangles.iter().flatten().find(|&&v| v as usize >= n) {
            return Err(Error::Internal(format!("vertex {v} is not an input vertex: its UV is unknown")));
        }
        let mut present = vec![false; n];
        let mut level_half: FxHashMap<[u32; 2], u32> = FxHashMap::default();
        for (f, t) in triangles.iter().enumerate() {
            for k in 0..3 {
                present[t[k] as usize] = true;
                level_half.insert([t[k], t[(k + 1) % 3]], f as u32);
            }
        }
        let first_steps = self.first_seam_steps(&present);
        let mut corners: Vec<[u32; 3]> = Vec::with_capacity(triangles.len());
        let mut faces = Vec::with_capacity(triangles.len());
        for (f, t) in triangles.iter().enumerate() {
            let mut wedge = [(0u32, 0u8); 3];
            for k in 0..3 {
                wedge[k] = self.wedge(t, k, &level_half, triangles, &first_steps).ok_or_else(|| {
                    Error::Internal(format!("level face {f} {t:?}: no wedge of vertex {} holds it", t[k]))
                })?;
            }
            if let Some(uvs) = &self.uvs {
                corners.push(wedge.map(|(g, j)| uvs.corners[g as usize][j as usize]));
            }
            if let Some(m) = &self.materials {
                faces.push(m.faces[wedge[0].0 as usize]);
            }
        }
        // Only the coordinates the level uses, in order of first use.
        let uvs = self.uvs.as_ref().map(|u| {
            let mut index = vec![u32::MAX; u.values.len()];
            let mut values = Vec::new();
            for c in corners.iter_mut().flatten() {
                if index[*c as usize] == u32::MAX {
                    index[*c as usize] = values.len() as u32;
                    values.push(u.values[*c as usize]);
                }
                *c = index[*c as usize];
            }
            CornerUvs { values, corners }
        });
        let materials =
            self.materials.as_ref().map(|m| Materials { libraries: m.libraries.clone(), names: m.names.clone(), faces });
        Ok((uvs, materials))
    }

    /// For each present seam vertex v and level seam edge v–x: the first input vertex of
    /// the seam path from v to x.
    fn first_seam_steps(&self, present: &[bool]) -> FxHashMap<[u32; 2], u32> {
        let mut steps = FxHashMap::default();
        for (v, neighbours) in self.seam_neighbours.iter().enumerate() {
            if !present[v] {
                continue;
            }
            for &first in neighbours {
                let (mut previous, mut current) = (v as u32, first);
                // A removed seam vertex lies on a line (two seam neighbours); the walk
                // ends at the next present vertex, or gives up on a broken path.
                let mut guard = self.seam_neighbours.len();
                while !present[current as usize] && guard > 0 {
                    let ahead = &self.seam_neighbours[current as usize];
                    let Some(&next) = ahead.iter().find(|&&w| w != previous).filter(|_| ahead.len() == 2) else {
                        break;
                    };
                    (previous, current) = (current, next);
                    guard -= 1;
                }
                if present[current as usize] {
                    steps.entry([v as u32, current]).or_insert(first);
                }
            }
        }
        steps
    }

    /// The input (face, corner) whose UV corner `k` of level face `t` takes.
    fn wedge(
        &self,
        t: &[u32; 3],
        k: usize,
        level_half: &FxHashMap<[u32; 2], u32>,
        triangles: &[[u32; 3]],
        first_steps: &FxHashMap<[u32; 2], u32>,
    ) -> Option<(u32, u8)> {
        let v = t[k];
        if self.seam_neighbours[v as usize].is_empty() {
            return Some(self.any_corner[v as usize]);
        }
        // Clockwise: from the face's edge v → a to the face across it, until a seam edge.
        // No ring of a level is this large; a walk that finds no seam gives up.
        let limit = 1 << 12;
        let mut a = t[(k + 1) % 3];
        for _ in 0..limit {
            if let Some(&step) = first_steps.get(&[v, a]) {
                return self.left_of(v, step);
            }
            let Some(&across) = level_half.get(&[a, v]) else { break };
            let u = triangles[across as usize];
            let j = u.iter().position(|&w| w == v)?;
            a = u[(j + 1) % 3];
        }
        // A boundary first: counter-clockwise from the face's edge b → v.
        let mut b = t[(k + 2) % 3];
        for _ in 0..limit {
            if let Some(&step) = first_steps.get(&[v, b]) {
                return self.left_of(step, v).and_then(|(f, _)| self.corner_of(f, v));
            }
            let across = *level_half.get(&[v, b])?;
            let u = triangles[across as usize];
            let j = u.iter().position(|&w| w == v)?;
            b = u[(j + 2) % 3];
        }
        None
    }

    /// The input face on the left of directed edge a → b and the corner of a in it.
    fn left_of(&self, a: u32, b: u32) -> Option<(u32, u8)> {
        self.half.get(&[a, b]).copied()
    }

    /// The corner of `v` in input face `f`.
    fn corner_of(&self, f: u32, v: u32) -> Option<(u32, u8)> {
        let k = self.triangles[f as usize].iter().position(|&w| w == v)?;
        Some((f, k as u8))
    }
}
