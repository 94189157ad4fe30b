// Glue between the cxx-generated bridge (src/ffi/mod.rs) and asperity's native C++ API.
// Converts rust::Slice / rust::Vec to the native calls; every function may throw, and
// cxx turns the exception into a Rust `Err` (see the trycatch below).
#pragma once

#include <cstdint>
#include <exception>
#include <memory>

#include "asperity/asperity.hpp"
#include "rust/cxx.h"

namespace rust {
namespace behavior {
// Catch everything, not only std::exception: nothing may unwind into Rust or terminate.
template <typename Try, typename Fail>
static void trycatch(Try&& func, Fail&& fail) noexcept try {
  func();
} catch (const std::exception& e) {
  fail(e.what());
} catch (...) {
  fail("unknown C++ exception");
}
}  // namespace behavior
}  // namespace rust

namespace asperity {
namespace ffi {

struct MeshCounts;
struct CsrArrays;
struct ExportArrays;
struct SplitOutcome;
struct DecimatedMesh;

std::unique_ptr<HalfEdgeMesh> new_halfedge_mesh();
rust::Vec<std::uint32_t> add_geometry(HalfEdgeMesh& mesh, rust::Slice<const double> positions,
                                      rust::Slice<const std::uint32_t> triangles);
void reserve_mesh(HalfEdgeMesh& mesh, std::size_t vertices, std::size_t edges, std::size_t faces);
MeshCounts mesh_counts(const HalfEdgeMesh& mesh);
ExportArrays export_arrays(const HalfEdgeMesh& mesh);
CsrArrays one_rings(const HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> vertices);
rust::Vec<std::uint32_t> valences(const HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> vertices);
rust::Vec<std::uint8_t> boundary_flags(const HalfEdgeMesh& mesh,
                                       rust::Slice<const std::uint32_t> vertices);
rust::Vec<std::uint8_t> flip_edges(HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> pairs);
SplitOutcome split_edges(HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> pairs,
                         rust::Slice<const double> points);
rust::Vec<std::uint8_t> insert_on_edges(HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> pairs,
                                        rust::Slice<const std::uint32_t> vertices,
                                        rust::Slice<const double> points);
rust::Vec<std::uint8_t> collapse_halfedges(HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> pairs,
                                           std::uint32_t required_degree, bool check_normals);
rust::Vec<std::uint32_t> garbage_collect(HalfEdgeMesh& mesh);

rust::Vec<double> vertex_quadrics(rust::Slice<const double> positions,
                                  rust::Slice<const std::uint32_t> triangles, double boundary_weight);
rust::Vec<double> quadric_errors(rust::Slice<const double> quadrics, rust::Slice<const double> points);
double symmetric_hausdorff(rust::Slice<const double> positions_a,
                           rust::Slice<const std::uint32_t> triangles_a,
                           rust::Slice<const double> positions_b,
                           rust::Slice<const std::uint32_t> triangles_b,
                           double points_per_area_unit, std::uint32_t seed);
DecimatedMesh openmesh_decimate(rust::Slice<const double> positions,
                                rust::Slice<const std::uint32_t> triangles, std::size_t target_vertices);
DecimatedMesh cgal_decimate(rust::Slice<const double> positions,
                            rust::Slice<const std::uint32_t> triangles, std::size_t target_vertices);
std::unique_ptr<DistanceTree> new_distance_tree(rust::Slice<const double> positions,
                                                rust::Slice<const std::uint32_t> triangles);
rust::Vec<double> tree_distances(const DistanceTree& tree, rust::Slice<const double> points, bool chained);
rust::Vec<std::uint32_t> self_intersections(rust::Slice<const double> positions,
                                            rust::Slice<const std::uint32_t> triangles);
rust::Vec<std::uint8_t> triangle_pairs_intersect(rust::Slice<const double> positions,
                                                 rust::Slice<const std::uint32_t> kept,
                                                 rust::Slice<const std::uint32_t> added,
                                                 rust::Slice<const std::uint32_t> pairs);

}  // namespace ffi
}  // namespace asperity
