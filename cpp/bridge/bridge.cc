// Glue implementations: copy between rust:: containers and the native API.
#include "asperity/src/ffi/mod.rs.h"

namespace asperity {
namespace ffi {
namespace {

template <typename T>
rust::Vec<T> to_rust(const std::vector<T>& in) {
  rust::Vec<T> out;
  out.reserve(in.size());
  for (const T& x : in) out.push_back(x);
  return out;
}

rust::Vec<std::uint8_t> to_rust(const std::vector<OpStatus>& in) {
  rust::Vec<std::uint8_t> out;
  out.reserve(in.size());
  for (OpStatus s : in) out.push_back(static_cast<std::uint8_t>(s));
  return out;
}

TriangleArrays arrays(rust::Slice<const double> p, rust::Slice<const std::uint32_t> t) {
  return TriangleArrays{p.data(), p.size(), t.data(), t.size()};
}

}  // namespace

std::unique_ptr<HalfEdgeMesh> new_halfedge_mesh() { return std::make_unique<HalfEdgeMesh>(); }

rust::Vec<std::uint32_t> add_geometry(HalfEdgeMesh& mesh, rust::Slice<const double> positions,
                                      rust::Slice<const std::uint32_t> triangles) {
  return to_rust(mesh.add_geometry(positions.data(), positions.size(), triangles.data(),
                                   triangles.size()));
}

void reserve_mesh(HalfEdgeMesh& mesh, std::size_t vertices, std::size_t edges, std::size_t faces) {
  mesh.reserve(vertices, edges, faces);
}

MeshCounts mesh_counts(const HalfEdgeMesh& mesh) {
  return MeshCounts{mesh.live_vertex_count(), mesh.live_edge_count(), mesh.live_face_count(),
                    mesh.vertex_slots()};
}

ExportArrays export_arrays(const HalfEdgeMesh& mesh) {
  const ExportedArrays e = mesh.export_arrays();
  return ExportArrays{to_rust(e.positions), to_rust(e.triangles), to_rust(e.vertex_remap)};
}

CsrArrays one_rings(const HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> vertices) {
  const Csr c = mesh.one_rings(vertices.data(), vertices.size());
  return CsrArrays{to_rust(c.offsets), to_rust(c.indices)};
}

rust::Vec<std::uint32_t> valences(const HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> vertices) {
  return to_rust(mesh.valences(vertices.data(), vertices.size()));
}

rust::Vec<std::uint8_t> boundary_flags(const HalfEdgeMesh& mesh,
                                       rust::Slice<const std::uint32_t> vertices) {
  return to_rust(mesh.boundary_flags(vertices.data(), vertices.size()));
}

rust::Vec<std::uint8_t> flip_edges(HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> pairs) {
  return to_rust(mesh.flip_edges(pairs.data(), pairs.size()));
}

SplitOutcome split_edges(HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> pairs,
                         rust::Slice<const double> points) {
  std::vector<std::uint32_t> new_vertices;
  const auto status =
      mesh.split_edges(pairs.data(), pairs.size(), points.data(), points.size(), new_vertices);
  return SplitOutcome{to_rust(status), to_rust(new_vertices)};
}

rust::Vec<std::uint8_t> insert_on_edges(HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> pairs,
                                        rust::Slice<const std::uint32_t> vertices,
                                        rust::Slice<const double> points) {
  return to_rust(mesh.insert_on_edges(pairs.data(), pairs.size(), vertices.data(), vertices.size(),
                                      points.data(), points.size()));
}

rust::Vec<std::uint8_t> collapse_halfedges(HalfEdgeMesh& mesh, rust::Slice<const std::uint32_t> pairs,
                                           std::uint32_t required_degree, bool check_normals) {
  return to_rust(mesh.collapse_halfedges(pairs.data(), pairs.size(), required_degree, check_normals));
}

rust::Vec<std::uint32_t> garbage_collect(HalfEdgeMesh& mesh) { return to_rust(mesh.garbage_collect()); }

rust::Vec<double> vertex_quadrics(rust::Slice<const double> positions,
                                  rust::Slice<const std::uint32_t> triangles, double boundary_weight) {
  return to_rust(asperity::vertex_quadrics(arrays(positions, triangles), boundary_weight));
}

rust::Vec<double> quadric_errors(rust::Slice<const double> quadrics, rust::Slice<const double> points) {
  return to_rust(asperity::quadric_errors(quadrics.data(), quadrics.size(), points.data(), points.size()));
}

double symmetric_hausdorff(rust::Slice<const double> positions_a,
                           rust::Slice<const std::uint32_t> triangles_a,
                           rust::Slice<const double> positions_b,
                           rust::Slice<const std::uint32_t> triangles_b,
                           double points_per_area_unit, std::uint32_t seed) {
  return asperity::symmetric_hausdorff(arrays(positions_a, triangles_a),
                                       arrays(positions_b, triangles_b), points_per_area_unit, seed);
}

std::unique_ptr<DistanceTree> new_distance_tree(rust::Slice<const double> positions,
                                                rust::Slice<const std::uint32_t> triangles) {
  return std::make_unique<DistanceTree>(arrays(positions, triangles));
}

rust::Vec<double> tree_distances(const DistanceTree& tree, rust::Slice<const double> points, bool chained) {
  return to_rust(tree.distances(points.data(), points.size(), chained));
}

DecimatedMesh openmesh_decimate(rust::Slice<const double> positions,
                                rust::Slice<const std::uint32_t> triangles, std::size_t target_vertices) {
  const DecimatedArrays d = asperity::openmesh_decimate(arrays(positions, triangles), target_vertices);
  return DecimatedMesh{to_rust(d.positions), to_rust(d.triangles)};
}

DecimatedMesh cgal_decimate(rust::Slice<const double> positions,
                            rust::Slice<const std::uint32_t> triangles, std::size_t target_vertices) {
  const DecimatedArrays d = asperity::cgal_decimate(arrays(positions, triangles), target_vertices);
  return DecimatedMesh{to_rust(d.positions), to_rust(d.triangles)};
}

rust::Vec<std::uint32_t> self_intersections(rust::Slice<const double> positions,
                                            rust::Slice<const std::uint32_t> triangles) {
  return to_rust(asperity::self_intersections(arrays(positions, triangles)));
}

rust::Vec<std::uint8_t> triangle_pairs_intersect(rust::Slice<const double> positions,
                                                 rust::Slice<const std::uint32_t> kept,
                                                 rust::Slice<const std::uint32_t> added,
                                                 rust::Slice<const std::uint32_t> pairs) {
  return to_rust(asperity::triangle_pairs_intersect(arrays(positions, kept), arrays(positions, added), pairs.data(),
                                                    pairs.size()));
}

}  // namespace ffi
}  // namespace asperity
