//! The FFI spine: a `cxx` bridge to asperity's C++ adapter over OpenMesh (half-edge
//! topology) and CGAL (quadrics, Hausdorff distance, self-intersections), and safe
//! wrappers around it. Every call is batched — one call per operation, never per
//! element — and returns a `Result`: C++ exceptions become [`Error::Native`](crate::error::Error::Native).
//!
//! By concern: `halfedge.rs` (the OpenMesh half-edge store), `cgal.rs` (quadrics, Hausdorff
//! distance, self-intersections, point distances), `decimators.rs` (the reference
//! decimators `compare` runs); the bridge and the flat-array helpers are here.

use glam::DVec3;

mod cgal;
mod decimators;
mod halfedge;

pub use cgal::{
    DistanceTree, HausdorffOptions, hausdorff_distance, point_distances, quadric_errors, self_intersections,
    triangle_pairs_intersect, vertex_quadrics,
};
pub use decimators::{cgal_decimate, openmesh_decimate};
pub use halfedge::{CollapseOptions, Csr, Exported, HalfEdgeMesh, OpStatus};

pub use crate::analysis::Quadric;

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
        fn reserve_mesh(mesh: Pin<&mut HalfEdgeMesh>, vertices: usize, edges: usize, faces: usize) -> Result<()>;
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
        #[namespace = "asperity"]
        type DistanceTree;

        fn new_distance_tree(positions: &[f64], triangles: &[u32]) -> Result<UniquePtr<DistanceTree>>;
        fn tree_distances(tree: &DistanceTree, points: &[f64], chained: bool) -> Result<Vec<f64>>;
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
