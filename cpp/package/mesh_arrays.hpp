// OpenMesh meshes to and from the flat arrays the bridge exchanges (a PolyMesh's polygons
// triangulated), and the vertex properties asperity adds (names start with "asperity:",
// persistent: OpenMesh's writers keep them).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <OpenMesh/Core/Utils/PropertyManager.hh>

#include "asperity/errors.hpp"
#include "rust/cxx.h"  // first: rust::Slice, rust::Vec
#include "asperity/bridge.rs.h"

namespace asperity {

/// A point or vector, x y z.
using Vec3 = std::array<double, 3>;
/// Three vertex indices.
using Triangle = std::array<std::uint32_t, 3>;
/// What a pipeline call did.
using Report = ffi::Report;

namespace impl {

/// Bridge slices over vectors.
template <class T>
rust::Slice<const T> slice(const std::vector<T>& values) {
  return rust::Slice<const T>(values.data(), values.size());
}

/// x y z triples as vectors.
inline std::vector<Vec3> vectors(const rust::Vec<double>& flat) {
  std::vector<Vec3> out(flat.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]};
  return out;
}

/// One byte per flag (the bridge's form of a selection).
inline std::vector<std::uint8_t> bytes(const std::vector<bool>& flags) {
  return std::vector<std::uint8_t>(flags.begin(), flags.end());
}

/// The vertex property `name` of `mesh` (made if missing), persistent, so that OpenMesh's
/// writers keep it: the .om format always, PLY with IO::Options::Custom.
template <class T, class Mesh>
OpenMesh::PropertyManager<OpenMesh::VPropHandleT<T>> vertex_property(Mesh& mesh, const char* name) {
  auto property = OpenMesh::getOrMakeProperty<OpenMesh::VertexHandle, T>(mesh, name);
  mesh.property(property.getRawProperty()).set_persistent(true);
  return property;
}

/// The mesh's faces as triangles (OpenMesh vertex indices, three each) and, when `faces`
/// is given, the face each triangle comes from. A polygon (an OpenMesh PolyMesh's quads
/// and n-gons) is cut into n − 2 triangles by the ear clipping asperity's file readers use.
template <class Mesh>
void triangles_of(const Mesh& mesh, const std::vector<double>& positions, std::vector<std::uint32_t>& triangles,
                  std::vector<typename Mesh::FaceHandle>* faces = nullptr) {
  std::vector<std::uint32_t> counts, corners;
  counts.reserve(mesh.n_faces());
  corners.reserve(3 * mesh.n_faces());
  bool polygons = false;
  for (auto f : mesh.faces()) {
    std::uint32_t n = 0;
    for (auto v : mesh.fv_range(f)) {
      corners.push_back(std::uint32_t(v.idx()));
      ++n;
    }
    counts.push_back(n);
    polygons |= n != 3;
  }
  if (polygons) {
    const auto cut = call([&] { return ffi::triangulate(slice(positions), slice(counts), slice(corners)); });
    triangles.assign(cut.begin(), cut.end());
  } else {
    triangles = std::move(corners);
  }
  if (faces) {
    faces->clear();
    for (auto f : mesh.faces()) {
      const std::size_t n = counts[std::size_t(f.idx())];
      faces->insert(faces->end(), n - 2, f);
    }
  }
}

}  // namespace impl

/// The mesh's positions and triangles as flat arrays (OpenMesh vertex indices); polygon
/// faces (a PolyMesh) are triangulated (impl::triangles_of), and `faces`, when given,
/// receives the face each triangle comes from.
template <class Mesh>
void to_arrays(const Mesh& mesh, std::vector<double>& positions, std::vector<std::uint32_t>& triangles,
               std::vector<typename Mesh::FaceHandle>* faces = nullptr) {
  // Deleted elements keep their slots until garbage collection, so vertex indices would not
  // be the arrays' (#36: "face refers to vertex 6474 but there are 6474 vertices").
  std::size_t deleted = 0;
  if (mesh.has_vertex_status()) {
    for (auto v : mesh.all_vertices()) deleted += mesh.status(v).deleted() ? 1 : 0;
  }
  if (mesh.has_face_status()) {
    for (auto f : mesh.all_faces()) deleted += mesh.status(f).deleted() ? 1 : 0;
  }
  if (deleted > 0) {
    throw InputError("the mesh has " + std::to_string(deleted) +
                     " deleted vertices or faces not yet collected: call mesh.garbage_collection() first");
  }
  positions.clear();
  positions.reserve(3 * mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    positions.insert(positions.end(), {double(p[0]), double(p[1]), double(p[2])});
  }
  impl::triangles_of(mesh, positions, triangles, faces);
}

/// Replaces the mesh's contents with the arrays.
template <class Mesh>
void from_arrays(Mesh& mesh, const ffi::MeshArrays& arrays) {
  mesh.clean();
  std::vector<typename Mesh::VertexHandle> handles;
  handles.reserve(arrays.positions.size() / 3);
  for (std::size_t i = 0; i + 2 < arrays.positions.size(); i += 3) {
    handles.push_back(mesh.add_vertex(typename Mesh::Point(arrays.positions[i], arrays.positions[i + 1], arrays.positions[i + 2])));
  }
  for (std::size_t i = 0; i + 2 < arrays.triangles.size(); i += 3) {
    mesh.add_face(handles[arrays.triangles[i]], handles[arrays.triangles[i + 1]], handles[arrays.triangles[i + 2]]);
  }
}

/// The mesh's texture coordinates per triangle corner, u v in `triangles`' corner order (6
/// per triangle; `faces`: the face each triangle comes from, as impl::triangles_of gives
/// them): its halfedge texcoords, else its vertex texcoords; empty when it has neither.
template <class Mesh>
std::vector<double> corner_uvs(const Mesh& mesh, const std::vector<std::uint32_t>& triangles,
                               const std::vector<typename Mesh::FaceHandle>& faces) {
  std::vector<double> uvs;
  const bool per_corner = mesh.has_halfedge_texcoords2D();
  if (!per_corner && !mesh.has_vertex_texcoords2D()) return uvs;
  uvs.reserve(2 * triangles.size());
  for (std::size_t k = 0; k < triangles.size(); ++k) {
    const auto v = mesh.vertex_handle(triangles[k]);
    typename Mesh::TexCoord2D t(0, 0);
    if (!per_corner) t = mesh.texcoord2D(v);
    if (per_corner) {
      // The corner of v in its face: the face's halfedge that points to v.
      for (auto h : mesh.fh_range(faces[k / 3])) {
        if (mesh.to_vertex_handle(h) == v) t = mesh.texcoord2D(h);
      }
    }
    uvs.push_back(double(t[0]));
    uvs.push_back(double(t[1]));
  }
  return uvs;
}

/// A mesh of a hierarchy level or refinement, each vertex's input vertex index in the
/// vertex property "asperity:id", and, when the input had texture coordinates, halfedge
/// texcoords (one per face corner: a seam vertex has one per side).
template <class Mesh>
Mesh level_mesh(const ffi::LevelArrays& level) {
  Mesh mesh;
  from_arrays(mesh, level.mesh);
  auto id = impl::vertex_property<int>(mesh, "asperity:id");
  for (auto v : mesh.vertices()) id[v] = int(level.ids[std::size_t(v.idx())]);
  if (!level.corner_uvs.empty() && level.corner_uvs.size() == 6 * mesh.n_faces()) {
    mesh.request_halfedge_texcoords2D();
    for (auto f : mesh.faces()) {
      const auto& t = level.mesh.triangles;
      const std::size_t base = 3 * std::size_t(f.idx());
      for (auto h : mesh.fh_range(f)) {
        const auto v = std::uint32_t(mesh.to_vertex_handle(h).idx());
        for (std::size_t k = 0; k < 3; ++k) {
          if (t[base + k] != v) continue;
          const auto u = level.corner_uvs[2 * (base + k)], w = level.corner_uvs[2 * (base + k) + 1];
          mesh.set_texcoord2D(h, typename Mesh::TexCoord2D(u, w));
        }
      }
    }
  }
  return mesh;
}

}  // namespace asperity
