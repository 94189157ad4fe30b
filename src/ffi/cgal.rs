//! CGAL's measures behind the bridge: vertex quadrics, the Hausdorff distance,
//! self-intersections and exact triangle-pair tests, point-to-surface distances.

use glam::DVec3;

use super::{flat_positions, sys};
use crate::analysis::Quadric;
use crate::error::{Error, Result};
use crate::mesh::{FaceId, Mesh};

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

/// Distance from each point to the nearest point of `mesh` (CGAL AABB tree).
///
/// # Errors
/// [`Error::InvalidInput`] for an inconsistent mesh; [`Error::Native`] when CGAL refuses it.
pub fn point_distances(points: &[DVec3], mesh: &Mesh) -> Result<Vec<f64>> {
    mesh.check()?;
    DistanceTree::new(&mesh.positions, &mesh.triangles)?.distances(points)
}

/// An AABB tree over triangles (CGAL's `AABB_tree` of `Triangle_3`), built once and asked
/// the distance of batches of points; it needs no half-edge structure, so any set of
/// faces (a piece of a mesh) makes one. Threads may ask one tree at once.
pub struct DistanceTree(cxx::UniquePtr<sys::DistanceTree>);

// SAFETY: the C++ DistanceTree owns its triangles and CGAL's tree (no thread-local or
// global state), so it may move to another thread. Its only query after construction is
// the const `distances`: the constructor builds both the tree and its search tree for
// distance queries, and CGAL guards the lazy builds a const query could start with its
// own mutex (`AABB_tree::build_mutex`), so concurrent queries read a finished structure.
#[allow(unsafe_code)]
unsafe impl Send for sys::DistanceTree {}
#[allow(unsafe_code)]
unsafe impl Sync for sys::DistanceTree {}

impl DistanceTree {
    /// The tree of `triangles` over `positions`.
    ///
    /// # Errors
    /// [`Error::Native`] for no faces, an index out of range, a face repeating a vertex or a
    /// non-finite coordinate.
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> Result<Self> {
        Ok(DistanceTree(sys::new_distance_tree(flat_positions(positions), triangles.as_flattened())?))
    }

    /// Distance from each point to the nearest point of the triangles, each query starting
    /// from the closest point of the one before (neighbouring points: a face's samples).
    ///
    /// # Errors
    /// [`Error::Native`] if CGAL fails.
    pub fn distances(&self, points: &[DVec3]) -> Result<Vec<f64>> {
        self.query(points, true)
    }

    /// As [`DistanceTree::distances`], each distance found from its point alone (CGAL's own
    /// search for a starting point): where two faces are equally near within rounding, a
    /// chained query's last bits may depend on the point before it, so callers whose
    /// batches are not fixed ask this way.
    ///
    /// # Errors
    /// [`Error::Native`] if CGAL fails.
    pub fn distances_each_alone(&self, points: &[DVec3]) -> Result<Vec<f64>> {
        self.query(points, false)
    }

    fn query(&self, points: &[DVec3], chained: bool) -> Result<Vec<f64>> {
        let tree = self.0.as_ref().ok_or_else(|| Error::Native("the distance tree is null".into()))?;
        Ok(sys::tree_distances(tree, flat_positions(points), chained)?)
    }
}

/// CGAL's exact intersection test of triangle pairs over `positions`: a pair names
/// `kept[k]` by k < `kept.len()` and `added[i]` by `kept.len() + i`; one flag per pair
/// (the narrow phase of `hierarchy::added_triangle_intersections`).
///
/// # Errors
/// [`Error::Native`] if CGAL fails.
pub fn triangle_pairs_intersect(
    positions: &[DVec3],
    kept: &[[u32; 3]],
    added: &[[u32; 3]],
    pairs: &[[u32; 2]],
) -> Result<Vec<u8>> {
    Ok(sys::triangle_pairs_intersect(
        flat_positions(positions),
        kept.as_flattened(),
        added.as_flattened(),
        pairs.as_flattened(),
    )?)
}
