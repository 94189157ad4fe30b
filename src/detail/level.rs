//! What an operator sees at a hierarchy level: the level's mesh (compacted, with input
//! ids), its adjacency and normals, the full surface analysis on demand, and the input's
//! bounding box that recipes' normalised coordinates and relative sizes refer to.

use std::sync::OnceLock;

use glam::DVec3;

use crate::analysis::{AnalysisOptions, FaceGeometry, NormalWeighting, SurfaceAnalysis, analyze, vertex_normals};
use crate::error::Result;
use super::recipe::Attenuate;
use crate::hierarchy::LevelMesh;
use crate::mesh::{Adjacency, Mesh};

/// The input's bounding box: normalised coordinates (0 to 1 per axis) and the diagonal
/// that amplitudes and radii are fractions of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxFrame {
    /// Lower corner.
    pub min: DVec3,
    /// Size along each axis.
    pub extent: DVec3,
    /// Length of the diagonal.
    pub diagonal: f64,
}

impl BoxFrame {
    /// The bounding box of `mesh` (a unit box for an empty mesh).
    pub fn of(mesh: &Mesh) -> Self {
        let (min, max) = mesh.bounding_box().unwrap_or((DVec3::ZERO, DVec3::ONE));
        let extent = max - min;
        BoxFrame { min, extent, diagonal: extent.length().max(f64::MIN_POSITIVE) }
    }

    /// `p` in normalised coordinates (a flat axis maps to 0.5).
    pub fn normalise(&self, p: DVec3) -> DVec3 {
        let axis = |v: f64, lo: f64, e: f64| if e > 0.0 { (v - lo) / e } else { 0.5 };
        DVec3::new(
            axis(p.x, self.min.x, self.extent.x),
            axis(p.y, self.min.y, self.extent.y),
            axis(p.z, self.min.z, self.extent.z),
        )
    }

    /// The point with normalised coordinates `n`.
    pub fn point(&self, n: [f64; 3]) -> DVec3 {
        self.min + DVec3::from_array(n) * self.extent
    }

    /// The centre of the box.
    pub fn centre(&self) -> DVec3 {
        self.min + 0.5 * self.extent
    }
}

/// One level's mesh and what operators read from it.
pub struct LevelView {
    /// Refinement level (0: base domain).
    pub level: usize,
    /// Levels between this one and the input (0 at the input's level).
    pub depth: usize,
    /// The mesh, compacted.
    pub mesh: Mesh,
    /// Input id (or id of a vertex made by subdivision) of each vertex of `mesh`.
    pub ids: Vec<u32>,
    /// Vertex adjacency.
    pub adjacency: Adjacency,
    /// Unit vertex normals (angle-weighted).
    pub normals: Vec<DVec3>,
    /// The refinement level each vertex of `mesh` first belongs to in the hierarchy (0: a
    /// base vertex; `level` for vertices made at this level by subdivision); every vertex
    /// is taken to belong to `level` until [`LevelView::with_appearance`] says otherwise.
    pub appear: Vec<u32>,
    analysis: OnceLock<SurfaceAnalysis>,
}

impl std::fmt::Debug for LevelView {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LevelView {{ level: {}, vertices: {} }}", self.level, self.ids.len())
    }
}

impl LevelView {
    /// Wraps a level's mesh.
    pub fn new(level: usize, depth: usize, level_mesh: LevelMesh) -> Self {
        let LevelMesh { mesh, ids } = level_mesh;
        let adjacency = Adjacency::of(&mesh);
        let faces = FaceGeometry::of(&mesh);
        let normals = vertex_normals(&mesh, &adjacency, &faces, NormalWeighting::Angle);
        let appear = vec![level as u32; mesh.vertex_count()];
        LevelView { level, depth, mesh, ids, adjacency, normals, appear, analysis: OnceLock::new() }
    }

    /// This view with each vertex's level of appearance read from `by_id` (indexed by id).
    pub fn with_appearance(mut self, by_id: &[u32]) -> Self {
        self.appear = self.ids.iter().map(|&id| by_id.get(id as usize).copied().unwrap_or(self.level as u32)).collect();
        self
    }

    /// The level number l of eq. 4.5 for vertex `v` under `attenuate`: the step's
    /// ([`LevelView::thesis_level`]), the vertex's own (1 for a vertex of the input's level
    /// only, one more per coarser level it belongs to), or 1.
    pub fn attenuation_level(&self, v: usize, attenuate: Attenuate) -> f64 {
        match attenuate {
            Attenuate::None => 1.0,
            Attenuate::Step => self.thesis_level(),
            Attenuate::Vertex => {
                let steps = (self.level + self.depth) as f64;
                steps - f64::from(self.appear[v]) + 1.0
            }
        }
    }

    /// The level number l of eq. 4.5: 1 at the input's level, one more per coarser level.
    pub fn thesis_level(&self) -> f64 {
        (self.depth + 1) as f64
    }

    /// Curvatures, voting tensors and feature classes of this level (computed once).
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] for an inconsistent mesh.
    pub fn analysis(&self) -> Result<&SurfaceAnalysis> {
        if let Some(a) = self.analysis.get() {
            return Ok(a);
        }
        let a = analyze(&self.mesh, &AnalysisOptions::default())?;
        Ok(self.analysis.get_or_init(|| a))
    }

    /// Mean edge length (the unit of eq. 4.15's distances).
    pub fn mean_edge_length(&self) -> f64 {
        let (mut sum, mut count) = (0.0, 0usize);
        for t in &self.mesh.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a < b {
                    sum += self.mesh.positions[a as usize].distance(self.mesh.positions[b as usize]);
                    count += 1;
                }
            }
        }
        if count == 0 { 1.0 } else { (sum / count as f64).max(f64::MIN_POSITIVE) }
    }

    /// Breadth-first rings from `centres` (local indices, visited in the given order):
    /// each reached vertex gets (ring number, nearest centre); unreached ones `None`.
    pub fn rings_from(&self, centres: &[usize], rings: usize) -> Vec<Option<(usize, usize)>> {
        let mut reach = vec![None; self.ids.len()];
        let mut frontier = Vec::new();
        for &c in centres {
            if reach[c].is_none() {
                reach[c] = Some((0, c));
                frontier.push(c);
            }
        }
        // A ring count past the mesh's reach ends where the rings stop growing (#36:
        // `rings = 1000000000000` ran empty rounds for hours).
        for k in 1..=rings {
            if frontier.is_empty() {
                break;
            }
            let mut next = Vec::new();
            for &u in &frontier {
                let centre = reach[u].map_or(u, |(_, c)| c);
                for &w in self.adjacency.neighbours(u) {
                    if reach[w as usize].is_none() {
                        reach[w as usize] = Some((k, centre));
                        next.push(w as usize);
                    }
                }
            }
            frontier = next;
        }
        reach
    }
}
