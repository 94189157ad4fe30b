//! The FFI spine: a `cxx` bridge to asperity's C++ adapter over OpenMesh (half-edge
//! topology) and CGAL (quadrics, Hausdorff distance, self-intersections), and safe
//! wrappers around it. Every call is batched — one call per operation, never per
//! element — and returns a `Result`: C++ exceptions become [`Error::Native`].

use glam::DVec3;

use crate::error::{Error, Result};
use crate::mesh::{Aabb, BoxGrid, FaceId, Mesh, VertexId, certainly_apart};

#[cxx::bridge(namespace = "asperity::ffi")]
mod sys {
    /// Live element counts of the half-edge store.
    struct MeshCounts {
        /// Live (not deleted) vertices.
        vertices: usize,
        /// Live edges.
        edges: usize,
        /// Live faces.
        faces: usize,
        /// Vertex slots, deleted ones included: every vertex index is below this.
        vertex_slots: usize,
    }

    /// Adjacency in compressed sparse row form.
    struct CsrArrays {
        offsets: Vec<u32>,
        indices: Vec<u32>,
    }

    /// Exported arrays and the store-index → exported-index vertex remap.
    struct ExportArrays {
        positions: Vec<f64>,
        triangles: Vec<u32>,
        vertex_remap: Vec<u32>,
    }

    /// Per-split status and inserted vertex.
    struct SplitOutcome {
        status: Vec<u8>,
        new_vertices: Vec<u32>,
    }

    /// A decimated mesh from a reference decimator.
    struct DecimatedMesh {
        positions: Vec<f64>,
        triangles: Vec<u32>,
    }

    unsafe extern "C++" {
        include!("asperity/cpp/bridge/bridge.h");

        #[namespace = "asperity"]
        type HalfEdgeMesh;

        fn new_halfedge_mesh() -> Result<UniquePtr<HalfEdgeMesh>>;
        fn add_geometry(mesh: Pin<&mut HalfEdgeMesh>, positions: &[f64], triangles: &[u32]) -> Result<Vec<u32>>;
        fn mesh_counts(mesh: &HalfEdgeMesh) -> Result<MeshCounts>;
        fn export_arrays(mesh: &HalfEdgeMesh) -> Result<ExportArrays>;
        fn one_rings(mesh: &HalfEdgeMesh, vertices: &[u32]) -> Result<CsrArrays>;
        fn valences(mesh: &HalfEdgeMesh, vertices: &[u32]) -> Result<Vec<u32>>;
        fn boundary_flags(mesh: &HalfEdgeMesh, vertices: &[u32]) -> Result<Vec<u8>>;
        fn flip_edges(mesh: Pin<&mut HalfEdgeMesh>, pairs: &[u32]) -> Result<Vec<u8>>;
        fn split_edges(mesh: Pin<&mut HalfEdgeMesh>, pairs: &[u32], points: &[f64]) -> Result<SplitOutcome>;
        fn insert_on_edges(
            mesh: Pin<&mut HalfEdgeMesh>,
            pairs: &[u32],
            vertices: &[u32],
            points: &[f64],
        ) -> Result<Vec<u8>>;
        fn collapse_halfedges(
            mesh: Pin<&mut HalfEdgeMesh>,
            pairs: &[u32],
            required_degree: u32,
            check_normals: bool,
        ) -> Result<Vec<u8>>;
        fn garbage_collect(mesh: Pin<&mut HalfEdgeMesh>) -> Result<Vec<u32>>;

        fn vertex_quadrics(positions: &[f64], triangles: &[u32], boundary_weight: f64) -> Result<Vec<f64>>;
        fn quadric_errors(quadrics: &[f64], points: &[f64]) -> Result<Vec<f64>>;
        fn symmetric_hausdorff(
            positions_a: &[f64],
            triangles_a: &[u32],
            positions_b: &[f64],
            triangles_b: &[u32],
            points_per_area_unit: f64,
            seed: u32,
        ) -> Result<f64>;
        fn point_distances(points: &[f64], positions: &[f64], triangles: &[u32]) -> Result<Vec<f64>>;
        fn openmesh_decimate(positions: &[f64], triangles: &[u32], target_vertices: usize) -> Result<DecimatedMesh>;
        fn cgal_decimate(positions: &[f64], triangles: &[u32], target_vertices: usize) -> Result<DecimatedMesh>;
        fn self_intersections(positions: &[f64], triangles: &[u32]) -> Result<Vec<u32>>;
        fn triangle_pairs_intersect(positions: &[f64], kept: &[u32], added: &[u32], pairs: &[u32]) -> Result<Vec<u8>>;
    }
}

pub use sys::MeshCounts;

/// Marks "no index" in remaps returned by the native layer.
pub const INVALID_INDEX: u32 = u32::MAX;

fn flat_positions(positions: &[DVec3]) -> &[f64] {
    bytemuck::cast_slice(positions)
}

fn unflatten_positions(flat: &[f64]) -> Vec<DVec3> {
    flat.chunks_exact(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect()
}

fn flat_pairs(pairs: &[[u32; 2]]) -> &[u32] {
    pairs.as_flattened()
}

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

/// A Garland–Heckbert quadric: the upper triangle of a symmetric 4×4 matrix, row-major
/// (q00 q01 q02 q03 q11 q12 q13 q22 q23 q33).
#[derive(Debug, Clone, Copy, PartialEq, Default, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(transparent)]
pub struct Quadric(pub [f64; 10]);

impl Quadric {
    /// The quadric error [p 1] Q [p 1]ᵀ (a sum of squared plane distances).
    pub fn error(&self, p: DVec3) -> f64 {
        let [a, b, c, d, e, f, g, h, i, j] = self.0;
        let (x, y, z) = (p.x, p.y, p.z);
        x * (a * x + 2.0 * (b * y + c * z + d)) + y * (e * y + 2.0 * (f * z + g)) + z * (h * z + 2.0 * i) + j
    }

    /// The total weight of the planes summed into the quadric: the trace of its 3×3 part
    /// (a plane with normal n adds |n|²).
    pub fn weight(&self) -> f64 {
        self.0[0] + self.0[4] + self.0[7]
    }

    /// The weighted mean of the squared plane distances at `p`: [`Quadric::error`] divided
    /// by [`Quadric::weight`] (meshoptimizer's normalisation), so a quadric that has
    /// absorbed many planes is not dearer for that alone. Zero for an empty quadric.
    pub fn mean_error(&self, p: DVec3) -> f64 {
        let w = self.weight();
        if w > 0.0 { (self.error(p) / w).max(0.0) } else { 0.0 }
    }

    /// Adds `scale` times `other`.
    pub fn add_scaled(&mut self, other: &Quadric, scale: f64) {
        for (a, b) in self.0.iter_mut().zip(other.0) {
            *a += scale * b;
        }
    }
}

/// Per-vertex Garland–Heckbert quadrics from CGAL's `GarlandHeckbert_plane_policies`
/// (Garland & Heckbert 1997): the sum of the plane quadrics of the incident faces, plus
/// `boundary_weight` (CGAL's discontinuity multiplier, default 100) times the quadric of
/// the plane through each boundary edge perpendicular to its face.
///
/// # Errors
/// [`Error::InvalidInput`] for an inconsistent mesh; [`Error::Native`] when CGAL refuses it
/// (non-manifold or degenerate faces).
pub fn vertex_quadrics(mesh: &Mesh, boundary_weight: f64) -> Result<Vec<Quadric>> {
    mesh.check()?;
    let flat = sys::vertex_quadrics(flat_positions(&mesh.positions), mesh.triangles.as_flattened(), boundary_weight)?;
    Ok(bytemuck::cast_slice(&flat).to_vec())
}

/// The quadric error vᵀQv of each point under the matching quadric.
///
/// # Errors
/// [`Error::InvalidInput`] when the counts differ.
pub fn quadric_errors(quadrics: &[Quadric], points: &[DVec3]) -> Result<Vec<f64>> {
    if quadrics.len() != points.len() {
        return Err(Error::InvalidInput(format!("{} quadrics for {} points", quadrics.len(), points.len())));
    }
    Ok(sys::quadric_errors(bytemuck::cast_slice(quadrics), flat_positions(points))?)
}

/// Sampling for [`hausdorff_distance`].
#[derive(Debug, Clone, Copy)]
pub struct HausdorffOptions {
    /// Sample density; 0 lets CGAL choose.
    pub points_per_area_unit: f64,
    /// Seed of CGAL's sampler, fixed so results are reproducible.
    pub seed: u32,
}

impl Default for HausdorffOptions {
    fn default() -> Self {
        HausdorffOptions { points_per_area_unit: 0.0, seed: 0 }
    }
}

/// Approximate symmetric Hausdorff distance between two meshes, by CGAL's
/// `Polygon_mesh_processing::approximate_symmetric_Hausdorff_distance` (sampled).
///
/// # Errors
/// [`Error::InvalidInput`] for an inconsistent mesh; [`Error::Native`] when CGAL refuses a
/// mesh (no faces, non-manifold faces).
pub fn hausdorff_distance(a: &Mesh, b: &Mesh, options: HausdorffOptions) -> Result<f64> {
    a.check()?;
    b.check()?;
    Ok(sys::symmetric_hausdorff(
        flat_positions(&a.positions),
        a.triangles.as_flattened(),
        flat_positions(&b.positions),
        b.triangles.as_flattened(),
        options.points_per_area_unit,
        options.seed,
    )?)
}

/// Pairs of intersecting faces (CGAL's `self_intersections`), each pair ordered and the
/// list sorted. Faces sharing a vertex or an edge intersect only if they overlap beyond it.
///
/// # Errors
/// [`Error::InvalidInput`] for an inconsistent mesh; [`Error::Native`] when CGAL refuses it.
pub fn self_intersections(mesh: &Mesh) -> Result<Vec<[FaceId; 2]>> {
    mesh.check()?;
    let flat = sys::self_intersections(flat_positions(&mesh.positions), mesh.triangles.as_flattened())?;
    Ok(flat.chunks_exact(2).map(|p| [FaceId(p[0]), FaceId(p[1])]).collect())
}

/// The intersecting pairs of triangles with at least one from `added`, all over
/// `positions`, sorted: index k < `kept.len()` names `kept[k]`, and `kept.len() + i` names
/// `added[i]`. Triangles sharing a vertex or an edge intersect only if they overlap beyond
/// it (the rules of CGAL's `self_intersections`, with CGAL's exact predicates); pairs
/// within `kept` are not tested, so checking a planned retriangulation against the surface
/// it joins costs one pass over `kept` plus work proportional to the retriangulation.
///
/// The broad phase is a [`BoxGrid`] over the added triangles, queried by every triangle on
/// all threads; of the pairs whose boxes overlap, those the certified plane-side filter
/// ([`certainly_apart`]) cannot separate go to CGAL in batches, also across threads.
///
/// # Errors
/// [`Error::InvalidInput`] for an out-of-range index or a non-finite coordinate;
/// [`Error::Native`] if CGAL fails.
pub fn added_triangle_intersections(
    positions: &[DVec3],
    kept: &[[u32; 3]],
    added: &[[u32; 3]],
) -> Result<Vec<[u32; 2]>> {
    use rayon::prelude::*;
    for (i, t) in kept.iter().chain(added).enumerate() {
        for &v in t {
            let p = positions
                .get(v as usize)
                .ok_or_else(|| Error::InvalidInput(format!("triangle {i} names vertex {v} of {}", positions.len())))?;
            if !p.is_finite() {
                return Err(Error::InvalidInput(format!("vertex {v} of triangle {i} has a non-finite coordinate")));
            }
        }
    }
    let bbox =
        |t: &[u32; 3]| Aabb::of_triangle(positions[t[0] as usize], positions[t[1] as usize], positions[t[2] as usize]);
    let grid = BoxGrid::new(added.par_iter().map(bbox).collect());
    let nk = kept.len() as u32;
    // Candidates: kept against added, then added against added (each pair once), whose
    // boxes overlap and which the plane-side filter cannot tell apart.
    const CHUNK: usize = 1 << 12;
    let near_kept = kept.par_chunks(CHUNK).enumerate().map(|(c, part)| {
        let mut pairs = Vec::new();
        for (k, t) in part.iter().enumerate() {
            let k = (c * CHUNK + k) as u32;
            grid.query(&bbox(t), |i| {
                if !certainly_apart(positions, *t, added[i as usize]) {
                    pairs.push([k, nk + i]);
                }
            });
        }
        pairs
    });
    let near_added = grid.boxes().par_chunks(CHUNK).enumerate().map(|(c, part)| {
        let mut pairs = Vec::new();
        for (i, b) in part.iter().enumerate() {
            let i = (c * CHUNK + i) as u32;
            grid.query(b, |j| {
                if j > i && !certainly_apart(positions, added[i as usize], added[j as usize]) {
                    pairs.push([nk + i, nk + j]);
                }
            });
        }
        pairs
    });
    let candidates: Vec<[u32; 2]> = near_kept.chain(near_added).flatten_iter().collect();
    let flat = flat_positions(positions);
    let hits: Vec<Vec<[u32; 2]>> = candidates
        .par_chunks(CHUNK)
        .map(|part| {
            let flags =
                sys::triangle_pairs_intersect(flat, kept.as_flattened(), added.as_flattened(), part.as_flattened())?;
            Ok(part.iter().zip(flags).filter(|(_, f)| *f != 0).map(|(p, _)| *p).collect())
        })
        .collect::<Result<_>>()?;
    let mut pairs: Vec<[u32; 2]> = hits.into_iter().flatten().collect();
    pairs.sort_unstable();
    Ok(pairs)
}

/// OpenMesh's `DecimaterT` with `ModQuadricT` down to `target_vertices` (a reference for
/// `asperity compare`).
///
/// # Errors
/// [`Error::InvalidInput`] for an inconsistent mesh; [`Error::Native`] when OpenMesh refuses it.
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
/// [`Error::InvalidInput`] for an inconsistent mesh; [`Error::Native`] when CGAL refuses it.
pub fn cgal_decimate(mesh: &Mesh, target_vertices: usize) -> Result<Mesh> {
    mesh.check()?;
    let d = sys::cgal_decimate(flat_positions(&mesh.positions), mesh.triangles.as_flattened(), target_vertices)?;
    Ok(decimated(d))
}

fn decimated(d: sys::DecimatedMesh) -> Mesh {
    Mesh::new(unflatten_positions(&d.positions), d.triangles.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect())
}

/// Distance from each point to the nearest point of `mesh` (CGAL AABB tree).
///
/// # Errors
/// [`Error::InvalidInput`] for an inconsistent mesh; [`Error::Native`] when CGAL refuses it.
pub fn point_distances(points: &[DVec3], mesh: &Mesh) -> Result<Vec<f64>> {
    mesh.check()?;
    Ok(sys::point_distances(flat_positions(points), flat_positions(&mesh.positions), mesh.triangles.as_flattened())?)
}
