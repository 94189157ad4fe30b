// asperity — geometric measures from CGAL 5.5 on triangle arrays.
//
// Garland–Heckbert quadrics (CGAL's GarlandHeckbert_plane_policies), symmetric Hausdorff
// distance (Polygon_mesh_processing::approximate_symmetric_Hausdorff_distance) and
// self-intersections. Inputs are xyz triples and index triples; errors throw NativeError.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "asperity/halfedge_mesh.hpp"

namespace asperity {

/// A triangle mesh given by arrays (borrowed).
struct TriangleArrays {
  const double* xyz;
  std::size_t n_coords;
  const std::uint32_t* tris;
  std::size_t n_indices;
};

/// Per-vertex Garland–Heckbert quadrics: for each vertex the 10 upper-triangle entries of the
/// symmetric 4x4 matrix, row-major (q00 q01 q02 q03 q11 q12 q13 q22 q23 q33). Sum of the
/// plane quadrics of the incident faces plus `boundary_weight` times the quadric of the
/// perpendicular plane through each boundary edge (CGAL's discontinuity multiplier).
std::vector<double> vertex_quadrics(const TriangleArrays& mesh, double boundary_weight);

/// Quadric error v^T Q v of each point (xyz) under the matching quadric (10 values).
std::vector<double> quadric_errors(const double* quadrics, std::size_t n_quadric_values,
                                   const double* xyz, std::size_t n_coords);

/// Approximate symmetric Hausdorff distance, sampling `points_per_area_unit` (0: CGAL's
/// default) with a fixed random seed so the result is reproducible.
double symmetric_hausdorff(const TriangleArrays& a, const TriangleArrays& b,
                           double points_per_area_unit, unsigned seed);

/// An AABB tree over a triangle soup (CGAL's AABB_tree of Triangle_3, with its distance
/// queries accelerated), built once and asked the distance of batches of points: the
/// faces need no half-edge structure, so a piece of a mesh's faces is enough. Faces that
/// repeat a vertex are refused, as the half-edge meshes of the other measures refuse them.
class DistanceTree {
 public:
  explicit DistanceTree(const TriangleArrays& mesh);
  ~DistanceTree();
  DistanceTree(const DistanceTree&) = delete;
  DistanceTree& operator=(const DistanceTree&) = delete;

  /// Distance from each point (xyz) to the nearest point of the triangles. `chained`: each
  /// query starts from the closest point of the one before (for neighbouring points;
  /// where two faces are equally near within rounding, the last bits of a distance may
  /// then depend on the point before), else from CGAL's own search (each distance
  /// depends on its point alone).
  std::vector<double> distances(const double* xyz, std::size_t n_coords, bool chained) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

/// Pairs of intersecting faces (f0 g0 f1 g1 ..., each pair with f < g, sorted).
std::vector<std::uint32_t> self_intersections(const TriangleArrays& mesh);

/// For each pair (s, t) of `pairs` (a flat list), whether the two triangles intersect,
/// over the vertices of `xyz` (the n_coords of `kept` and `added` must be equal): indices
/// below the number of kept triangles name kept ones, the rest added ones after them.
/// Triangles sharing a vertex or an edge intersect only if they overlap beyond it, as in
/// Polygon_mesh_processing::self_intersections (CGAL's exact predicates). The narrow phase
/// of asperity's intersection guard; the caller finds the pairs whose boxes overlap.
std::vector<std::uint8_t> triangle_pairs_intersect(const TriangleArrays& kept, const TriangleArrays& added,
                                                   const std::uint32_t* pairs, std::size_t n_values);

}  // namespace asperity
