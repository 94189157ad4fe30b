//! The plain mesh exchange type: positions, triangles and optional per-vertex attributes.
//! Everything reads and writes [`Mesh`]; only connectivity-changing algorithms use the
//! half-edge store in [`crate::ffi`]. Validation and polygon triangulation live here too.

mod adjacency;
mod box_grid;
mod loop_subdivision;
mod plane_side;
pub mod primitives;
mod repair;
mod triangulate;
mod unit;
pub mod uv;
mod validate;

/// The largest coordinate a generated surface may reach (terrain heights, detail steps'
/// moves): far above any real use, far below where squares of coordinates (normals,
/// distances) overflow. Steps past it are refused naming their parameters.
pub const MAX_COORDINATE: f64 = 1e100;

use std::collections::BTreeMap;

use glam::DVec3;

pub use crate::ids::{FaceId, VertexId};
pub use adjacency::Adjacency;
pub use box_grid::{Aabb, BoxGrid};
pub use loop_subdivision::loop_subdivide;
pub use plane_side::{certain_orientation, certainly_apart};
pub use repair::{
    DegenerateRemoval, RepairReport, VertexOrigins, drop_unreferenced_vertices, orient_faces, remove_degenerate_faces,
    remove_duplicate_faces, repair, repair_with_origins, split_non_manifold_fans,
};
pub use triangulate::{triangulate_polygon, triangulate_polygons};
pub use unit::UnitFrame;
pub use validate::{TopologyCounts, ValidationReport, is_degenerate_face, repeats_a_vertex, used_vertices};

use crate::error::{Error, Result};

/// An RGB colour with 8 bits per channel.
pub type Rgb = [u8; 3];

/// `a` blended towards `b` by `s` (0: `a`, 1: `b`), each channel a + s·(b − a), rounded.
pub fn blend_rgb(a: Rgb, b: Rgb, s: f64) -> Rgb {
    [0, 1, 2].map(|k| (f64::from(a[k]) + s * (f64::from(b[k]) - f64::from(a[k]))).round() as u8)
}

/// A triangle mesh with optional per-vertex attributes. Attribute vectors, when present,
/// have one entry per vertex.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Triangles as vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// Per-vertex normals.
    pub normals: Option<Vec<DVec3>>,
    /// Per-vertex colours.
    pub colors: Option<Vec<Rgb>>,
    /// Named per-vertex scalar properties (curvatures, feature classes, ...), in name order.
    pub scalars: BTreeMap<String, Vec<f64>>,
    /// Texture coordinates per triangle corner (see [`uv`]).
    pub uvs: Option<uv::CornerUvs>,
    /// Materials per face (OBJ `mtllib`/`usemtl`).
    pub materials: Option<uv::Materials>,
}

impl Mesh {
    /// A mesh from positions and triangles, without attributes.
    pub fn new(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Self {
        Mesh { positions, triangles, ..Default::default() }
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn face_count(&self) -> usize {
        self.triangles.len()
    }

    /// The volume enclosed, by the divergence theorem: the sum of the signed volumes of the
    /// tetrahedra joining the origin to each face. Positive for a closed mesh whose faces
    /// face outwards.
    pub fn signed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| self.positions[v as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Appends `other`'s vertices and faces. Colours are kept when both meshes have them
    /// (or this one is empty), normals and UVs likewise; scalars only where both have the name;
    /// materials only when this mesh is empty.
    pub fn append(&mut self, other: &Mesh) {
        let empty = self.positions.is_empty();
        let offset = self.positions.len() as u32;
        fn join<T: Clone>(mine: &mut Option<Vec<T>>, theirs: &Option<Vec<T>>, empty: bool) {
            match (mine.as_mut(), theirs) {
                (Some(a), Some(b)) => a.extend_from_slice(b),
                (None, Some(b)) if empty => *mine = Some(b.clone()),
                _ => *mine = None,
            }
        }
        join(&mut self.colors, &other.colors, empty);
        join(&mut self.normals, &other.normals, empty);
        self.uvs = match (self.uvs.take(), &other.uvs) {
            (Some(mut mine), Some(theirs)) => {
                let shift = mine.values.len() as u32;
                mine.values.extend_from_slice(&theirs.values);
                mine.corners.extend(theirs.corners.iter().map(|c| c.map(|i| i + shift)));
                Some(mine)
            }
            (None, Some(theirs)) if empty => Some(theirs.clone()),
            _ => None,
        };
        // Materials name files of their own: kept only when nothing is merged with them.
        self.materials = if empty { other.materials.clone() } else { None };
        if empty {
            self.scalars = other.scalars.clone();
        } else {
            self.scalars.retain(|name, _| other.scalars.contains_key(name));
            for (name, values) in &mut self.scalars {
                values.extend_from_slice(&other.scalars[name]);
            }
        }
        self.positions.extend_from_slice(&other.positions);
        self.triangles.extend(other.triangles.iter().map(|t| t.map(|v| v + offset)));
    }

    /// Keeps the faces `keep` marks (one flag per face), in order, with their UVs and
    /// materials; returns how many went.
    pub fn retain_faces(&mut self, keep: &[bool]) -> usize {
        fn retain<T>(values: &mut Vec<T>, keep: &[bool]) {
            let mut k = keep.iter();
            values.retain(|_| *k.next().expect("one flag per face"));
        }
        let before = self.triangles.len();
        retain(&mut self.triangles, keep);
        if let Some(uvs) = &mut self.uvs {
            retain(&mut uvs.corners, keep);
        }
        if let Some(m) = &mut self.materials {
            retain(&mut m.faces, keep);
        }
        before - self.triangles.len()
    }

    /// Axis-aligned bounding box `(min, max)`; `None` for a mesh without vertices.
    pub fn bounding_box(&self) -> Option<(DVec3, DVec3)> {
        bounding_box_of(&self.positions)
    }

    /// The three corner positions of triangle `f`.
    pub fn triangle_points(&self, f: usize) -> [DVec3; 3] {
        self.triangles[f].map(|v| self.positions[v as usize])
    }

    /// Checks that the arrays are consistent: finite coordinates, indices in range,
    /// attribute vectors of the right length.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the first offending vertex, face or attribute.
    pub fn check(&self) -> Result<()> {
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::InvalidInput(format!("vertex {i} has a non-finite coordinate")));
        }
        let n = self.positions.len();
        if n > u32::MAX as usize {
            return Err(Error::InvalidInput(format!("{n} vertices exceed the 32-bit index range")));
        }
        for (f, t) in self.triangles.iter().enumerate() {
            if let Some(v) = t.iter().find(|&&v| v as usize >= n) {
                return Err(Error::InvalidInput(format!("face {f} refers to vertex {v} but there are {n} vertices")));
            }
        }
        let check_len = |name: &str, len: usize| {
            if len == n {
                Ok(())
            } else {
                Err(Error::InvalidInput(format!("attribute `{name}` has {len} values for {n} vertices")))
            }
        };
        if let Some(v) = &self.normals {
            check_len("normals", v.len())?;
        }
        if let Some(v) = &self.colors {
            check_len("colors", v.len())?;
        }
        for (name, v) in &self.scalars {
            check_len(name, v.len())?;
        }
        if let Some(uvs) = &self.uvs {
            uvs.check(self.triangles.len())?;
        }
        if let Some(m) = &self.materials {
            if m.faces.len() != self.triangles.len() {
                return Err(Error::InvalidInput(format!(
                    "materials are given for {} of {} faces",
                    m.faces.len(),
                    self.triangles.len()
                )));
            }
            if let Some(f) = m.faces.iter().position(|&i| i != u32::MAX && i as usize >= m.names.len()) {
                return Err(Error::InvalidInput(format!("face {f} names a material that is not defined")));
            }
        }
        Ok(())
    }

    /// The validation report: counts, boundaries, manifoldness, components, genus.
    pub fn validate(&self) -> ValidationReport {
        ValidationReport::of(self)
    }
}

/// Axis-aligned bounding box `(min, max)` of `points`; `None` for no points.
pub fn bounding_box_of(points: &[DVec3]) -> Option<(DVec3, DVec3)> {
    let first = *points.first()?;
    Some(points.iter().fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))))
}
