// OpenMesh triangle meshes to and from the flat arrays the bridge exchanges, and the
// vertex properties asperity adds (names start with "asperity:").
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

/// The mesh's positions and triangles as flat arrays (OpenMesh vertex indices). Throws
/// InputError for a face that is not a triangle.
template <class Mesh>
void to_arrays(const Mesh& mesh, std::vector<double>& positions, std::vector<std::uint32_t>& triangles) {
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
  triangles.clear();
  positions.reserve(3 * mesh.n_vertices());
  triangles.reserve(3 * mesh.n_faces());
  for (auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    positions.insert(positions.end(), {double(p[0]), double(p[1]), double(p[2])});
  }
  for (auto f : mesh.faces()) {
    std::size_t corners = 0;
    for (auto v : mesh.fv_range(f)) {
      triangles.push_back(std::uint32_t(v.idx()));
      ++corners;
    }
    if (corners != 3) {
      throw InputError("face " + std::to_string(f.idx()) + " has " + std::to_string(corners) +
                       " corners: asperity takes triangle meshes");
    }
  }
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

/// The mesh's texture coordinates per face corner, u v in `to_arrays`' corner order (6
/// per triangle): its halfedge texcoords, else its vertex texcoords; empty when it has
/// neither.
template <class Mesh>
std::vector<double> corner_uvs(const Mesh& mesh) {
  std::vector<double> uvs;
  const bool per_corner = mesh.has_halfedge_texcoords2D();
  if (!per_corner && !mesh.has_vertex_texcoords2D()) return uvs;
  uvs.reserve(6 * mesh.n_faces());
  for (auto f : mesh.faces()) {
    for (auto v : mesh.fv_range(f)) {
      typename Mesh::TexCoord2D t(0, 0);
      if (!per_corner) t = mesh.texcoord2D(v);
      if (per_corner) {
        // The corner of v in f: the face's halfedge that points to v.
        for (auto h : mesh.fh_range(f)) {
          if (mesh.to_vertex_handle(h) == v) t = mesh.texcoord2D(h);
        }
      }
      uvs.push_back(double(t[0]));
      uvs.push_back(double(t[1]));
    }
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
  auto id = OpenMesh::getOrMakeProperty<OpenMesh::VertexHandle, int>(mesh, "asperity:id");
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

}  // namespace impl
}  // namespace asperity
