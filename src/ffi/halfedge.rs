//! The OpenMesh half-edge store behind the bridge: batched splits, flips, collapses and
//! insertions, and the rings read back out of it.

use glam::DVec3;

use super::{INVALID_INDEX, MeshCounts, flat_pairs, flat_positions, sys, unflatten_positions};
use crate::error::{Error, Result};
use crate::mesh::{FaceId, Mesh, VertexId};

/// Outcome of one element of a batched topological operation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum OpStatus {
    /// Applied.
    Done,
    /// The two vertices are not joined by an edge.
    NotAnEdge,
    /// OpenMesh's validity check refused it (`is_flip_ok`, `is_collapse_ok`).
    Rejected,
    /// The vertex does not have the required degree.
    WrongDegree,
    /// A vertex was removed by an earlier operation.
    Deleted,
    /// A vertex index beyond the vertex count.
    OutOfRange,
    /// The collapse would turn a surviving face upside down.
    FlipsNormal,
    /// The vertex to insert already has incident edges.
    NotIsolated,
}

impl OpStatus {
    fn from_code(code: u8) -> Result<Self> {
        Ok(match code {
            0 => OpStatus::Done,
            1 => OpStatus::NotAnEdge,
            2 => OpStatus::Rejected,
            3 => OpStatus::WrongDegree,
            4 => OpStatus::Deleted,
            5 => OpStatus::OutOfRange,
            6 => OpStatus::FlipsNormal,
            7 => OpStatus::NotIsolated,
            other => {
                return Err(Error::Internal(format!("unknown native status code {other}")));
            }
        })
    }

    fn decode(codes: &[u8]) -> Result<Vec<Self>> {
        codes.iter().map(|&c| Self::from_code(c)).collect()
    }
}

/// Options for [`HalfEdgeMesh::collapse_halfedges`].
#[derive(Debug, Clone, Copy, Default)]
pub struct CollapseOptions {
    /// Only collapse from vertices of this valence (0: any). 4 gives the four-face-cluster
    /// weld of the thesis (§3.1.7).
    pub required_degree: u32,
    /// Refuse collapses that would flip a surviving face's normal.
    pub check_normals: bool,
}

/// Vertex adjacency as compressed sparse rows: the neighbours of query `i` are
/// `indices[offsets[i]..offsets[i + 1]]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Csr {
    /// `queries + 1` offsets into `indices`.
    pub offsets: Vec<u32>,
    /// Concatenated neighbour lists.
    pub indices: Vec<u32>,
}

impl Csr {
    /// The neighbours of query `i`.
    pub fn row(&self, i: usize) -> &[u32] {
        &self.indices[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A mesh exported from the half-edge store.
#[derive(Debug, Clone)]
pub struct Exported {
    /// The live vertices and faces, compacted (vertex order kept).
    pub mesh: Mesh,
    /// Store vertex index → index in `mesh` ([`INVALID_INDEX`] for deleted vertices).
    pub vertex_remap: Vec<u32>,
}

/// An opaque half-edge mesh backed by an OpenMesh `TriMesh` with double-precision points:
/// the hierarchy's working topology.
pub struct HalfEdgeMesh {
    inner: cxx::UniquePtr<sys::HalfEdgeMesh>,
}

// SAFETY: the C++ HalfEdgeMesh owns all its state (an OpenMesh TriMesh and its property
// containers: no thread-local or global state), so it may move to another thread. It is
// never shared across threads: `HalfEdgeMesh` is not `Sync`, and every change takes
// `&mut`.
#[allow(unsafe_code)]
unsafe impl Send for sys::HalfEdgeMesh {}

impl std::fmt::Debug for HalfEdgeMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.counts() {
            Ok(c) => write!(f, "HalfEdgeMesh {{ vertices: {}, edges: {}, faces: {} }}", c.vertices, c.edges, c.faces),
            Err(_) => write!(f, "HalfEdgeMesh {{ .. }}"),
        }
    }
}

impl HalfEdgeMesh {
    /// Builds the store from a mesh's positions and triangles (attributes are not carried).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for out-of-range indices or non-finite coordinates;
    /// [`Error::Topology`] naming the faces OpenMesh refused as non-manifold (or
    /// degenerate): faces are never dropped silently.
    pub fn from_mesh(mesh: &Mesh) -> Result<Self> {
        mesh.check()?;
        let mut inner = sys::new_halfedge_mesh()?;
        let rejected =
            sys::add_geometry(inner.pin_mut(), flat_positions(&mesh.positions), mesh.triangles.as_flattened())?;
        if !rejected.is_empty() {
            let shown: Vec<String> = rejected.iter().take(8).map(|f| format!("#{f}")).collect();
            let more = if rejected.len() > 8 { ", ..." } else { "" };
            return Err(Error::Topology {
                msg: format!(
                    "{} face(s) are non-manifold or degenerate and cannot be added to the half-edge mesh: {}{more}",
                    rejected.len(),
                    shown.join(", ")
                ),
                faces: rejected.into_iter().map(FaceId).collect(),
            });
        }
        Ok(HalfEdgeMesh { inner })
    }

    fn store(&self) -> Result<&sys::HalfEdgeMesh> {
        self.inner.as_ref().ok_or_else(|| Error::Internal("half-edge mesh is null".into()))
    }

    fn store_mut(&mut self) -> Result<std::pin::Pin<&mut sys::HalfEdgeMesh>> {
        self.inner.as_mut().ok_or_else(|| Error::Internal("half-edge mesh is null".into()))
    }

    /// Makes room for `vertices`, `edges` and `faces` (never less than the store holds), so
    /// a store that will grow to a known size reallocates nothing on the way.
    ///
    /// # Errors
    /// [`Error::Native`] if the native layer fails (out of memory).
    pub fn reserve(&mut self, vertices: usize, edges: usize, faces: usize) -> Result<()> {
        Ok(sys::reserve_mesh(self.store_mut()?, vertices, edges, faces)?)
    }

    /// Live vertex, edge and face counts, and the number of vertex slots.
    ///
    /// # Errors
    /// [`Error::Native`] if the native layer fails.
    pub fn counts(&self) -> Result<MeshCounts> {
        Ok(sys::mesh_counts(self.store()?)?)
    }

    /// Exports the live elements, compacted, with the vertex remap.
    ///
    /// # Errors
    /// [`Error::Native`] if the native layer fails.
    pub fn export(&self) -> Result<Exported> {
        let e = sys::export_arrays(self.store()?)?;
        let triangles = e.triangles.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        Ok(Exported { mesh: Mesh::new(unflatten_positions(&e.positions), triangles), vertex_remap: e.vertex_remap })
    }

    /// The 1-rings of `vertices`, counter-clockwise with respect to the face orientation,
    /// consecutive neighbours sharing a face. An interior vertex's ring starts at the target
    /// of its stored outgoing half-edge; a boundary vertex's ring is open and runs from one
    /// boundary neighbour to the other.
    ///
    /// # Errors
    /// [`Error::Native`] naming a vertex that is out of range or deleted.
    pub fn one_rings(&self, vertices: &[VertexId]) -> Result<Csr> {
        let c = sys::one_rings(self.store()?, bytemuck::cast_slice(vertices))?;
        Ok(Csr { offsets: c.offsets, indices: c.indices })
    }

    /// Valence (number of neighbours) of each vertex.
    ///
    /// # Errors
    /// [`Error::Native`] naming a vertex that is out of range or deleted.
    pub fn valences(&self, vertices: &[VertexId]) -> Result<Vec<u32>> {
        Ok(sys::valences(self.store()?, bytemuck::cast_slice(vertices))?)
    }

    /// Whether each vertex lies on a boundary.
    ///
    /// # Errors
    /// [`Error::Native`] naming a vertex that is out of range or deleted.
    pub fn boundary_flags(&self, vertices: &[VertexId]) -> Result<Vec<bool>> {
        Ok(sys::boundary_flags(self.store()?, bytemuck::cast_slice(vertices))?.into_iter().map(|b| b != 0).collect())
    }

    /// Flips the edges `[a, b]`, in order, each checked by OpenMesh's `is_flip_ok`.
    ///
    /// # Errors
    /// [`Error::Native`] if the native layer fails; refused flips are statuses, not errors.
    pub fn flip_edges(&mut self, edges: &[[u32; 2]]) -> Result<Vec<OpStatus>> {
        OpStatus::decode(&sys::flip_edges(self.store_mut()?, flat_pairs(edges))?)
    }

    /// Splits the edges `[a, b]` at the given points, in order; returns each status and
    /// the inserted vertex (`None` unless `Done`).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when the counts differ; [`Error::Native`] for a non-finite point.
    pub fn split_edges(&mut self, edges: &[[u32; 2]], points: &[DVec3]) -> Result<Vec<(OpStatus, Option<VertexId>)>> {
        if edges.len() != points.len() {
            return Err(Error::InvalidInput(format!("{} edges to split but {} points", edges.len(), points.len())));
        }
        let out = sys::split_edges(self.store_mut()?, flat_pairs(edges), flat_positions(points))?;
        let status = OpStatus::decode(&out.status)?;
        Ok(status
            .into_iter()
            .zip(out.new_vertices)
            .map(|(s, v)| (s, (v != INVALID_INDEX).then_some(VertexId(v))))
            .collect())
    }

    /// Splits the edges `[a, b]` by inserting the given isolated vertices (present in the
    /// store but on no face) moved to `points`, in order. Vertex indices stay fixed, which
    /// is what hierarchy refinement needs.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when the counts differ; [`Error::Native`] for a non-finite point.
    pub fn insert_on_edges(&mut self, edges: &[[u32; 2]], vertices: &[u32], points: &[DVec3]) -> Result<Vec<OpStatus>> {
        if edges.len() != points.len() || edges.len() != vertices.len() {
            return Err(Error::InvalidInput(format!(
                "{} edges to split, {} vertices and {} points",
                edges.len(),
                vertices.len(),
                points.len()
            )));
        }
        OpStatus::decode(&sys::insert_on_edges(self.store_mut()?, flat_pairs(edges), vertices, flat_positions(points))?)
    }

    /// Collapses the half-edges `[from, to]` in order (`from` is removed, `to` keeps its
    /// position), each checked by OpenMesh's `is_collapse_ok` and `options`.
    ///
    /// # Errors
    /// [`Error::Native`] if the native layer fails; refused collapses are statuses.
    pub fn collapse_halfedges(&mut self, halfedges: &[[u32; 2]], options: CollapseOptions) -> Result<Vec<OpStatus>> {
        let codes = sys::collapse_halfedges(
            self.store_mut()?,
            flat_pairs(halfedges),
            options.required_degree,
            options.check_normals,
        )?;
        OpStatus::decode(&codes)
    }

    /// Four-face-cluster welds (thesis §3.1.7): removes each degree-4 vertex `from` by
    /// collapsing it onto its neighbour `to`, refusing collapses that flip a face.
    ///
    /// # Errors
    /// As [`HalfEdgeMesh::collapse_halfedges`].
    pub fn weld_degree_four(&mut self, welds: &[[u32; 2]]) -> Result<Vec<OpStatus>> {
        self.collapse_halfedges(welds, CollapseOptions { required_degree: 4, check_normals: true })
    }

    /// Removes deleted elements. Returns old vertex index → new index ([`INVALID_INDEX`]
    /// for removed vertices); OpenMesh fills holes from the end, so order is not kept.
    ///
    /// # Errors
    /// [`Error::Native`] if the native layer fails.
    pub fn garbage_collect(&mut self) -> Result<Vec<u32>> {
        Ok(sys::garbage_collect(self.store_mut()?)?)
    }
}
