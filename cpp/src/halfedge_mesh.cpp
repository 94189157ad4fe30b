// OpenMesh-backed half-edge store: batched queries and topological operations.
#include "asperity/halfedge_mesh.hpp"

#include <cmath>
#include <algorithm>
#include <sstream>

#include <OpenMesh/Core/System/omstream.hh>

namespace asperity {
namespace {

using VH = TriMesh::VertexHandle;
using HH = TriMesh::HalfedgeHandle;
using FH = TriMesh::FaceHandle;

void require_multiple(std::size_t n, std::size_t k, const char* what) {
  if (n % k != 0) {
    std::ostringstream msg;
    msg << what << ": length " << n << " is not a multiple of " << k;
    throw NativeError(msg.str());
  }
}

/// Silences OpenMesh's "complex edge" chatter on std::cerr, once for the process: the
/// rejected faces are reported to the caller instead. OpenMesh connects its error stream
/// to std::cerr on first use without a lock, so stores built side by side (a partitioned
/// build's parts, #40) that both met their first refused face raced there and crashed
/// (1 run in 15 on the shared anchor in 4 parts); toggling the stream per call raced too.
/// C++'s static initialisation runs this once, whichever thread comes first.
void silence_openmesh_errors() {
  static const bool silenced = [] {
    omerr().disable();
    return true;
  }();
  (void)silenced;
}

TriMesh::Normal face_normal_with(const TriMesh& m, FH f, VH moved, const TriMesh::Point& to) {
  TriMesh::Point p[3];
  int i = 0;
  for (auto v : m.fv_range(f)) p[i++] = (v == moved) ? to : m.point(v);
  return OpenMesh::cross(p[1] - p[0], p[2] - p[0]);
}

}  // namespace

HalfEdgeMesh::HalfEdgeMesh() {
  silence_openmesh_errors();
  mesh_.request_vertex_status();
  mesh_.request_edge_status();
  mesh_.request_halfedge_status();
  mesh_.request_face_status();
}

std::vector<std::uint32_t> HalfEdgeMesh::add_geometry(const double* xyz, std::size_t n_coords,
                                                      const std::uint32_t* tris,
                                                      std::size_t n_indices) {
  require_multiple(n_coords, 3, "positions");
  require_multiple(n_indices, 3, "triangles");
  const std::size_t first = mesh_.n_vertices();
  const std::size_t n_new = n_coords / 3;
  for (std::size_t i = 0; i < n_new; ++i) {
    const double x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      std::ostringstream msg;
      msg << "vertex " << i << " has a non-finite coordinate";
      throw NativeError(msg.str());
    }
  }
  const std::size_t total = first + n_new;
  for (std::size_t i = 0; i < n_indices; ++i) {
    if (tris[i] >= total) {
      std::ostringstream msg;
      msg << "face " << i / 3 << " refers to vertex " << tris[i] << " but there are only "
          << total << " vertices";
      throw NativeError(msg.str());
    }
  }
  mesh_.reserve(total, total * 3, mesh_.n_faces() + n_indices / 3);
  for (std::size_t i = 0; i < n_new; ++i)
    mesh_.add_vertex(TriMesh::Point(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]));

  std::vector<std::uint32_t> rejected;
  silence_openmesh_errors();
  for (std::size_t f = 0; f < n_indices / 3; ++f) {
    const VH a(static_cast<int>(tris[3 * f])), b(static_cast<int>(tris[3 * f + 1])),
        c(static_cast<int>(tris[3 * f + 2]));
    if (a == b || b == c || a == c || !mesh_.add_face(a, b, c).is_valid())
      rejected.push_back(static_cast<std::uint32_t>(f));
  }
  return rejected;
}

void HalfEdgeMesh::reserve(std::size_t vertices, std::size_t edges, std::size_t faces) {
  mesh_.reserve(std::max(vertices, mesh_.n_vertices()), std::max(edges, mesh_.n_edges()),
                std::max(faces, mesh_.n_faces()));
}

std::size_t HalfEdgeMesh::live_vertex_count() const {
  std::size_t n = 0;
  for (auto v : mesh_.vertices()) n += mesh_.status(v).deleted() ? 0 : 1;
  return n;
}

std::size_t HalfEdgeMesh::live_face_count() const {
  std::size_t n = 0;
  for (auto f : mesh_.faces()) n += mesh_.status(f).deleted() ? 0 : 1;
  return n;
}

std::size_t HalfEdgeMesh::live_edge_count() const {
  std::size_t n = 0;
  for (auto e : mesh_.edges()) n += mesh_.status(e).deleted() ? 0 : 1;
  return n;
}

std::size_t HalfEdgeMesh::vertex_slots() const { return mesh_.n_vertices(); }

ExportedArrays HalfEdgeMesh::export_arrays() const {
  ExportedArrays out;
  out.vertex_remap.assign(mesh_.n_vertices(), kInvalidIndex);
  std::uint32_t next = 0;
  // Index loops (not range-for) so deleted elements are visited and skipped explicitly.
  for (std::size_t i = 0; i < mesh_.n_vertices(); ++i) {
    const VH v(static_cast<int>(i));
    if (mesh_.status(v).deleted()) continue;
    out.vertex_remap[i] = next++;
    const auto& p = mesh_.point(v);
    out.positions.insert(out.positions.end(), {p[0], p[1], p[2]});
  }
  for (std::size_t i = 0; i < mesh_.n_faces(); ++i) {
    const FH f(static_cast<int>(i));
    if (mesh_.status(f).deleted()) continue;
    for (auto v : mesh_.fv_range(f)) out.triangles.push_back(out.vertex_remap[v.idx()]);
  }
  return out;
}

VH HalfEdgeMesh::checked_vertex(std::uint32_t index) const {
  if (index >= mesh_.n_vertices()) {
    std::ostringstream msg;
    msg << "vertex " << index << " is out of range (" << mesh_.n_vertices() << " vertices)";
    throw NativeError(msg.str());
  }
  const VH v(static_cast<int>(index));
  if (mesh_.status(v).deleted()) {
    std::ostringstream msg;
    msg << "vertex " << index << " has been deleted";
    throw NativeError(msg.str());
  }
  return v;
}

Csr HalfEdgeMesh::one_rings(const std::uint32_t* vertices, std::size_t n) const {
  Csr out;
  out.offsets.reserve(n + 1);
  out.offsets.push_back(0);
  for (std::size_t i = 0; i < n; ++i) {
    const VH v = checked_vertex(vertices[i]);
    HH start = mesh_.halfedge_handle(v);
    if (start.is_valid()) {
      // OpenMesh keeps a boundary vertex's outgoing half-edge on the boundary (no face);
      // rotating counter-clockwise once puts the gap at the end of the ring.
      if (mesh_.is_boundary(start)) start = mesh_.ccw_rotated_halfedge_handle(start);
      HH h = start;
      do {
        out.indices.push_back(static_cast<std::uint32_t>(mesh_.to_vertex_handle(h).idx()));
        h = mesh_.ccw_rotated_halfedge_handle(h);
      } while (h != start);
    }
    out.offsets.push_back(static_cast<std::uint32_t>(out.indices.size()));
  }
  return out;
}

std::vector<std::uint32_t> HalfEdgeMesh::valences(const std::uint32_t* vertices,
                                                  std::size_t n) const {
  std::vector<std::uint32_t> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = mesh_.valence(checked_vertex(vertices[i]));
  return out;
}

std::vector<std::uint8_t> HalfEdgeMesh::boundary_flags(const std::uint32_t* vertices,
                                                       std::size_t n) const {
  std::vector<std::uint8_t> out(n);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = mesh_.is_boundary(checked_vertex(vertices[i])) ? 1 : 0;
  return out;
}

std::vector<OpStatus> HalfEdgeMesh::flip_edges(const std::uint32_t* pairs, std::size_t n_values) {
  require_multiple(n_values, 2, "flip pairs");
  std::vector<OpStatus> out(n_values / 2, OpStatus::Done);
  for (std::size_t i = 0; i < n_values / 2; ++i) {
    const std::uint32_t a = pairs[2 * i], b = pairs[2 * i + 1];
    if (a >= mesh_.n_vertices() || b >= mesh_.n_vertices()) { out[i] = OpStatus::OutOfRange; continue; }
    const VH va(static_cast<int>(a)), vb(static_cast<int>(b));
    if (mesh_.status(va).deleted() || mesh_.status(vb).deleted()) { out[i] = OpStatus::Deleted; continue; }
    const HH h = mesh_.find_halfedge(va, vb);
    if (!h.is_valid()) { out[i] = OpStatus::NotAnEdge; continue; }
    const auto e = mesh_.edge_handle(h);
    if (!mesh_.is_flip_ok(e)) { out[i] = OpStatus::Rejected; continue; }
    mesh_.flip(e);
  }
  return out;
}

std::vector<OpStatus> HalfEdgeMesh::split_edges(const std::uint32_t* pairs, std::size_t n_values,
                                                const double* xyz, std::size_t n_coords,
                                                std::vector<std::uint32_t>& new_vertices) {
  require_multiple(n_values, 2, "split pairs");
  if (n_coords != n_values / 2 * 3)
    throw NativeError("split_edges: need one point (3 coordinates) per edge");
  const std::size_t n = n_values / 2;
  std::vector<OpStatus> out(n, OpStatus::Done);
  new_vertices.assign(n, kInvalidIndex);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t a = pairs[2 * i], b = pairs[2 * i + 1];
    if (a >= mesh_.n_vertices() || b >= mesh_.n_vertices()) { out[i] = OpStatus::OutOfRange; continue; }
    const VH va(static_cast<int>(a)), vb(static_cast<int>(b));
    if (mesh_.status(va).deleted() || mesh_.status(vb).deleted()) { out[i] = OpStatus::Deleted; continue; }
    const HH h = mesh_.find_halfedge(va, vb);
    if (!h.is_valid()) { out[i] = OpStatus::NotAnEdge; continue; }
    const TriMesh::Point p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      std::ostringstream msg;
      msg << "split point " << i << " has a non-finite coordinate";
      throw NativeError(msg.str());
    }
    const VH nv = mesh_.split(mesh_.edge_handle(h), p);
    new_vertices[i] = static_cast<std::uint32_t>(nv.idx());
  }
  return out;
}

std::vector<OpStatus> HalfEdgeMesh::insert_on_edges(const std::uint32_t* pairs, std::size_t n_values,
                                                   const std::uint32_t* vertices, std::size_t n_vertices,
                                                   const double* xyz, std::size_t n_coords) {
  require_multiple(n_values, 2, "insertion pairs");
  const std::size_t n = n_values / 2;
  if (n_vertices != n || n_coords != 3 * n)
    throw NativeError("insert_on_edges: need one vertex and one point (3 coordinates) per edge");
  std::vector<OpStatus> out(n, OpStatus::Done);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t a = pairs[2 * i], b = pairs[2 * i + 1], v = vertices[i];
    if (a >= mesh_.n_vertices() || b >= mesh_.n_vertices() || v >= mesh_.n_vertices()) {
      out[i] = OpStatus::OutOfRange;
      continue;
    }
    const VH va(static_cast<int>(a)), vb(static_cast<int>(b)), vn(static_cast<int>(v));
    if (mesh_.status(va).deleted() || mesh_.status(vb).deleted() || mesh_.status(vn).deleted()) {
      out[i] = OpStatus::Deleted;
      continue;
    }
    if (!mesh_.is_isolated(vn)) { out[i] = OpStatus::NotIsolated; continue; }
    const HH h = mesh_.find_halfedge(va, vb);
    if (!h.is_valid()) { out[i] = OpStatus::NotAnEdge; continue; }
    const TriMesh::Point p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      std::ostringstream msg;
      msg << "insertion point " << i << " has a non-finite coordinate";
      throw NativeError(msg.str());
    }
    mesh_.set_point(vn, p);
    mesh_.split(mesh_.edge_handle(h), vn);
  }
  return out;
}

std::vector<OpStatus> HalfEdgeMesh::collapse_halfedges(const std::uint32_t* pairs,
                                                       std::size_t n_values,
                                                       std::uint32_t required_degree,
                                                       bool check_normals) {
  require_multiple(n_values, 2, "collapse pairs");
  std::vector<OpStatus> out(n_values / 2, OpStatus::Done);
  for (std::size_t i = 0; i < n_values / 2; ++i) {
    const std::uint32_t a = pairs[2 * i], b = pairs[2 * i + 1];
    if (a >= mesh_.n_vertices() || b >= mesh_.n_vertices()) { out[i] = OpStatus::OutOfRange; continue; }
    const VH from(static_cast<int>(a)), to(static_cast<int>(b));
    if (mesh_.status(from).deleted() || mesh_.status(to).deleted()) { out[i] = OpStatus::Deleted; continue; }
    const HH h = mesh_.find_halfedge(from, to);
    if (!h.is_valid()) { out[i] = OpStatus::NotAnEdge; continue; }
    if (required_degree != 0 && mesh_.valence(from) != required_degree) {
      out[i] = OpStatus::WrongDegree;
      continue;
    }
    if (!mesh_.is_collapse_ok(h)) { out[i] = OpStatus::Rejected; continue; }
    if (check_normals) {
      const FH gone0 = mesh_.face_handle(h), gone1 = mesh_.opposite_face_handle(h);
      bool flips = false;
      for (auto f : mesh_.vf_range(from)) {
        if (f == gone0 || f == gone1) continue;
        const auto before = face_normal_with(mesh_, f, from, mesh_.point(from));
        const auto after = face_normal_with(mesh_, f, from, mesh_.point(to));
        if (OpenMesh::dot(before, after) <= 0.0) { flips = true; break; }
      }
      if (flips) { out[i] = OpStatus::FlipsNormal; continue; }
    }
    mesh_.collapse(h);
  }
  return out;
}

std::vector<std::uint32_t> HalfEdgeMesh::garbage_collect() {
  // OpenMesh compacts by moving the last live element into each hole (order is not kept)
  // and leaves the handles of deleted elements untouched, so deletion is recorded first.
  const std::size_t n = mesh_.n_vertices();
  std::vector<VH> handles(n);
  std::vector<VH*> tracked(n);
  std::vector<bool> deleted(n);
  for (std::size_t i = 0; i < n; ++i) {
    handles[i] = VH(static_cast<int>(i));
    tracked[i] = &handles[i];
    deleted[i] = mesh_.status(handles[i]).deleted();
  }
  std::vector<HH*> no_halfedges;
  std::vector<FH*> no_faces;
  mesh_.garbage_collection(tracked, no_halfedges, no_faces);
  std::vector<std::uint32_t> remap(n, kInvalidIndex);
  for (std::size_t i = 0; i < n; ++i)
    if (!deleted[i]) remap[i] = static_cast<std::uint32_t>(handles[i].idx());
  return remap;
}

}  // namespace asperity
