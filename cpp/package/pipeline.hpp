// asperity's pipeline for C++ programs: simplify, detail with a recipe, and terrain, on
// OpenMesh triangle meshes (or on flat arrays through asperity::ffi).
//
//   #include <asperity/pipeline.hpp>
//   asperity::Report r = asperity::simplify(mesh, 500);          // mesh is a TriMesh
//   asperity::detail(mesh, recipe_toml);                          // rust::Error on failure
//   auto terrain = asperity::terrain<MyTriMesh>("classic", 257, 0.8, 7);
//
// The calls replace the mesh's contents (vertices, faces) with the result; vertex
// attributes other than positions are not carried over. Errors are thrown as rust::Error
// with asperity's one-line message (file, line or element named).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "rust/cxx.h"  // first: rust::Error, rust::Slice, rust::String
#include "asperity/bridge.rs.h"

namespace asperity {

using Report = ffi::Report;

/// The mesh's positions and triangle ids as flat arrays (OpenMesh vertex indices).
template <class Mesh>
void to_arrays(const Mesh& mesh, std::vector<double>& positions, std::vector<std::uint32_t>& triangles) {
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
    if (corners != 3) throw std::invalid_argument("asperity: only triangle meshes (face " + std::to_string(f.idx()) + ")");
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

/// Runs `call(positions, triangles)` on the mesh's arrays and replaces the mesh's contents
/// with the outcome's mesh; returns the outcome's report.
template <class Mesh, class Call>
Report run_in_place(Mesh& mesh, Call&& call) {
  std::vector<double> p;
  std::vector<std::uint32_t> t;
  to_arrays(mesh, p, t);
  auto out = call(rust::Slice<const double>(p.data(), p.size()), rust::Slice<const std::uint32_t>(t.data(), t.size()));
  from_arrays(mesh, out.mesh);
  return out.report;
}

/// Simplifies `mesh` in place to the base domain of asperity's 4-k hierarchy with at most
/// `target_vertices` vertices; `keep_features` is "none", "strong" or "all".
template <class Mesh>
Report simplify(Mesh& mesh, std::size_t target_vertices, const std::string& keep_features = "strong") {
  return run_in_place(mesh, [&](auto positions, auto triangles) {
    return ffi::simplify(positions, triangles, target_vertices, keep_features);
  });
}

/// Applies a detail recipe (TOML text; see docs/recipes.md) to `mesh` in place.
template <class Mesh>
Report detail(Mesh& mesh, const std::string& recipe_toml, bool no_self_intersections = false) {
  return run_in_place(mesh, [&](auto positions, auto triangles) {
    return ffi::detail(positions, triangles, recipe_toml, no_self_intersections);
  });
}

/// A "classic" or "smooth" diamond-square terrain of size × size points (size = 2^n + 1).
template <class Mesh>
Mesh terrain(const std::string& method, std::uint64_t size, double hurst, std::uint64_t seed) {
  auto out = ffi::terrain(method, size, hurst, seed);
  Mesh mesh;
  from_arrays(mesh, out.mesh);
  return mesh;
}

/// asperity's version.
inline std::string version() { return std::string(ffi::version()); }

}  // namespace asperity
