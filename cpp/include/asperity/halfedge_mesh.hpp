// asperity — native half-edge store over OpenMesh 9 (TriMesh, double precision).
//
// This is the C++ side of asperity's FFI spine. It is a plain C++ API (std::vector in,
// std::vector out) so that C++ programs can use it directly; the cxx bridge in
// cpp/bridge/ adapts it to Rust. Every operation is batched: one call per operation,
// never per element. Errors are reported by throwing asperity::NativeError.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace asperity {

/// Error raised by the native layer; its message names the offending element.
struct NativeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// OpenMesh triangle mesh with double-precision points.
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<OpenMesh::DefaultTraitsDouble>;

/// Marks a missing index in remaps and results.
constexpr std::uint32_t kInvalidIndex = 0xFFFFFFFFu;

/// Outcome of one element of a batched topological operation (mirrored by Rust's `OpStatus`).
enum class OpStatus : std::uint8_t {
  Done = 0,          ///< the operation was applied
  NotAnEdge = 1,     ///< the two vertices are not joined by an edge
  Rejected = 2,      ///< OpenMesh's validity check refused it (is_flip_ok / is_collapse_ok, boundary)
  WrongDegree = 3,   ///< the vertex does not have the required degree
  Deleted = 4,       ///< a vertex was already removed by an earlier operation
  OutOfRange = 5,    ///< a vertex index beyond the vertex count
  FlipsNormal = 6,   ///< the collapse would turn a surviving face upside down
  NotIsolated = 7,   ///< the vertex to insert already has incident edges
};

/// Vertex adjacency in compressed sparse row form: the neighbours of query i are
/// `indices[offsets[i] .. offsets[i+1]]`.
struct Csr {
  std::vector<std::uint32_t> offsets;
  std::vector<std::uint32_t> indices;
};

/// Arrays exported from the half-edge store.
struct ExportedArrays {
  std::vector<double> positions;          ///< xyz per live vertex
  std::vector<std::uint32_t> triangles;   ///< three exported vertex indices per live face
  std::vector<std::uint32_t> vertex_remap;///< store index -> exported index (kInvalidIndex if deleted)
};

/// Half-edge mesh: the hierarchy's working topology.
class HalfEdgeMesh {
 public:
  HalfEdgeMesh();

  /// Appends vertices (xyz triples) and triangles (index triples). Returns the indices
  /// (within `triangles`) of faces that OpenMesh refused as non-manifold ("complex
  /// edge/vertex"); those faces are not in the mesh. Throws on out-of-range indices or
  /// non-finite coordinates.
  std::vector<std::uint32_t> add_geometry(const double* xyz, std::size_t n_coords,
                                          const std::uint32_t* tris, std::size_t n_indices);

  /// Room for this many vertices, edges and faces in OpenMesh's arrays (never less than
  /// they hold): a mesh that will grow to a known size reallocates nothing on the way.
  void reserve(std::size_t vertices, std::size_t edges, std::size_t faces);
  std::size_t live_vertex_count() const;
  std::size_t live_face_count() const;
  std::size_t live_edge_count() const;
  /// Number of vertex slots, deleted ones included (indices are below this).
  std::size_t vertex_slots() const;

  /// Live vertices and faces, compacted, with the vertex remap. Does not modify the store.
  ExportedArrays export_arrays() const;

  /// 1-rings of the given vertices. Order: counter-clockwise with respect to the face
  /// orientation, consecutive neighbours sharing a face. Interior vertex: starts at the
  /// target of the vertex's stored outgoing half-edge. Boundary vertex: the ring is open;
  /// it starts at the neighbour across the boundary edge that follows the gap and ends
  /// at the neighbour across the boundary edge before it.
  Csr one_rings(const std::uint32_t* vertices, std::size_t n) const;
  std::vector<std::uint32_t> valences(const std::uint32_t* vertices, std::size_t n) const;
  std::vector<std::uint8_t> boundary_flags(const std::uint32_t* vertices, std::size_t n) const;

  /// Flips the edges given as vertex pairs (a0 b0 a1 b1 ...), in order.
  std::vector<OpStatus> flip_edges(const std::uint32_t* pairs, std::size_t n_values);
  /// Splits the edges given as vertex pairs at the given points (xyz per pair), in order.
  /// `new_vertices[i]` is the inserted vertex, or kInvalidIndex when status is not Done.
  std::vector<OpStatus> split_edges(const std::uint32_t* pairs, std::size_t n_values,
                                    const double* xyz, std::size_t n_coords,
                                    std::vector<std::uint32_t>& new_vertices);
  /// Splits the edges given as vertex pairs by inserting existing isolated vertices (one
  /// per pair), moved to the given points (xyz per pair), in order: the refinement of a
  /// hierarchy whose vertex indices are fixed for its whole life.
  std::vector<OpStatus> insert_on_edges(const std::uint32_t* pairs, std::size_t n_values,
                                        const std::uint32_t* vertices, std::size_t n_vertices,
                                        const double* xyz, std::size_t n_coords);
  /// Collapses half-edges from -> to (pairs), removing `from`; `to` keeps its position.
  /// `required_degree` > 0 restricts to vertices of that valence (4: four-face-cluster
  /// welds). With `check_normals`, a collapse that flips a surviving face is refused.
  std::vector<OpStatus> collapse_halfedges(const std::uint32_t* pairs, std::size_t n_values,
                                           std::uint32_t required_degree, bool check_normals);
  /// Removes deleted elements; returns old vertex index -> new index (kInvalidIndex if deleted).
  std::vector<std::uint32_t> garbage_collect();

  /// Direct access for C++ integrators.
  TriMesh& openmesh() { return mesh_; }
  const TriMesh& openmesh() const { return mesh_; }

 private:
  TriMesh::VertexHandle checked_vertex(std::uint32_t index) const;
  TriMesh mesh_;
};

}  // namespace asperity
