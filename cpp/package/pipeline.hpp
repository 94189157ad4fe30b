// asperity for C++ programs on OpenMesh triangle meshes. This header includes the whole
// package:
//
//   asperity::repair(mesh);                              // what --repair does, in place
//   std::string report = asperity::validate(mesh);       // asperity info's report (JSON)
//   double d = asperity::hausdorff(mesh, other);         // share of the diagonal
//   asperity::simplify(mesh, 500);                       // the base domain, in place
//   asperity::detail(mesh, recipe_toml);                 // a recipe (docs/recipes.md)
//   asperity::Hierarchy<Mesh> h(mesh, options);          // levels, parametrization,
//   Mesh out = h.refine(my_operator);                    //   refinement with C++ operators
//   asperity::analyze(mesh);                             // curvature, feature properties
//   auto values = asperity::noise(points, noise_options);
//   auto land = asperity::terrain<Mesh>(terrain_options);
//
// Meshes are OpenMesh TriMeshes or PolyMeshes (polygons are triangulated as the file
// readers do). Errors are thrown as asperity::InputError (bad input; the command line's
// exit 2), asperity::InternalError (exit 1) or asperity::Cancelled (a progress function
// said stop), all std::runtime_error, with asperity's one-line message. The in-place calls replace the mesh's contents; vertex attributes other than
// positions are not carried over.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <OpenMesh/Core/Utils/color_cast.hh>

#include "asperity/analysis.hpp"
#include "asperity/errors.hpp"
#include "asperity/fields.hpp"
#include "asperity/hierarchy.hpp"
#include "asperity/mesh_arrays.hpp"
#include "asperity/noise.hpp"
#include "asperity/terrain.hpp"

namespace asperity {

namespace impl {

/// Runs `call(positions, triangles)` on the mesh's arrays and replaces the mesh's contents
/// with the outcome's mesh; returns the outcome's report.
template <class Mesh, class Call>
Report run_in_place(Mesh& mesh, Call&& bridge_call) {
  std::vector<double> p;
  std::vector<std::uint32_t> t;
  to_arrays(mesh, p, t);
  auto out = call([&] { return bridge_call(slice(p), slice(t)); });
  from_arrays(mesh, out.mesh);
  // Vertex colours the result has (a detail recipe's [color] table) are requested and set.
  if (!out.colors.empty() && out.colors.size() == 3 * mesh.n_vertices()) {
    mesh.request_vertex_colors();
    for (auto v : mesh.vertices()) {
      const auto i = 3 * std::size_t(v.idx());
      mesh.set_color(v, OpenMesh::color_cast<typename Mesh::Color>(
                            OpenMesh::Vec3uc(out.colors[i], out.colors[i + 1], out.colors[i + 2])));
    }
  }
  return out.report;
}

}  // namespace impl

/// Simplifies `mesh` in place to the base domain of asperity's 4-k hierarchy with at most
/// `target_vertices` vertices (1 to the mesh's count: more, or 0, is an InputError, as on the
/// command line); `keep_features` is "none", "corners", "strong" or "all". (For every
/// option and the levels, use asperity::Hierarchy.)
template <class Mesh>
Report simplify(Mesh& mesh, std::size_t target_vertices, const std::string& keep_features = "strong") {
  return impl::run_in_place(mesh, [&](auto positions, auto triangles) {
    return ffi::simplify(positions, triangles, target_vertices, keep_features);
  });
}

/// Repairs `mesh` in place as the command line's `--repair` does (degenerate and duplicate
/// faces removed, non-manifold vertices and edges split, faces oriented, unreferenced
/// vertices dropped), so that a mesh the other calls refuse can be used. Each vertex of the
/// result carries the index of the input vertex it came from in the vertex property
/// "asperity:source" (a split copy: the vertex it copies). Returns what was done, as one
/// line ("nothing to repair" when nothing was).
template <class Mesh>
std::string repair(Mesh& mesh) {
  std::vector<double> p;
  std::vector<std::uint32_t> t;
  to_arrays(mesh, p, t);
  auto out = impl::call([&] { return ffi::repair(impl::slice(p), impl::slice(t)); });
  from_arrays(mesh, out.mesh);
  auto source = impl::vertex_property<int>(mesh, "asperity:source");
  for (auto v : mesh.vertices()) source[v] = int(out.source[std::size_t(v.idx())]);
  return std::string(out.report);
}

/// `asperity info`'s validation report of `mesh`, as JSON: counts, boundary loops,
/// manifoldness, orientation, components, Euler characteristic, genus, degenerate faces.
template <class Mesh>
std::string validate(const Mesh& mesh) {
  std::vector<double> p;
  std::vector<std::uint32_t> t;
  to_arrays(mesh, p, t);
  return std::string(impl::call([&] { return ffi::validate(impl::slice(p), impl::slice(t)); }));
}

/// The two-sided Hausdorff distance between `reference` and `other` (CGAL), as a share of
/// the reference's bounding-box diagonal (measured in its unit frame: no unit enters).
template <class MeshA, class MeshB>
double hausdorff(const MeshA& reference, const MeshB& other) {
  std::vector<double> p, q;
  std::vector<std::uint32_t> t, u;
  to_arrays(reference, p, t);
  to_arrays(other, q, u);
  return impl::call([&] { return ffi::hausdorff(impl::slice(p), impl::slice(t), impl::slice(q), impl::slice(u)); });
}

/// Settings laid over a detail recipe's `[hierarchy]` table, each only where set (the
/// command line's `detail` flags, Python's `detail` keywords); the same keys as the table.
struct HierarchySettings {
  /// A vertex count ("377") or a share of the input's ("5%").
  std::optional<std::string> target_vertices;
  /// Stop after this many levels.
  std::optional<std::uint64_t> levels;
  /// Never remove a vertex whose error exceeds this share of the bounding-box diagonal.
  std::optional<double> max_error;
  /// "none", "corners", "strong" or "all".
  std::optional<std::string> keep_features;
  /// "along-lines" or "keep".
  std::optional<std::string> feature_vertices;
  /// Weights of the removal and swap errors in E(v) (eq. 4.1).
  std::optional<double> removal_weight;
  std::optional<double> swap_weight;
  /// Leave out the clusters whose new faces would cut the surface.
  std::optional<bool> intersection_guard;
  /// Build in this many parts (a partitioned build, the command line's --chunks).
  std::optional<std::uint64_t> chunks;
};

/// Applies a detail recipe (TOML text; see docs/recipes.md) to `mesh` in place; a recipe
/// with a `[color]` table also requests and sets the mesh's vertex colours. As on the
/// command line and in Python, self-intersections the detail makes are resolved unless
/// `no_self_intersections` is false (`--allow-self-intersections`). `settings` replace the
/// recipe's `[hierarchy]` keys they set.
template <class Mesh>
Report detail(Mesh& mesh, const std::string& recipe_toml, const HierarchySettings& settings,
              bool no_self_intersections = true) {
  impl::Fields f;
  f.add("target_vertices", settings.target_vertices).add("levels", settings.levels).add("max_error", settings.max_error);
  f.add("keep_features", settings.keep_features).add("feature_vertices", settings.feature_vertices);
  f.add("removal_weight", settings.removal_weight).add("swap_weight", settings.swap_weight);
  f.add("intersection_guard", settings.intersection_guard).add("chunks", settings.chunks);
  const std::string fields = f.json();
  return impl::run_in_place(mesh, [&](auto positions, auto triangles) {
    return ffi::detail(positions, triangles, recipe_toml, fields, no_self_intersections);
  });
}

/// `detail` with the recipe's `[hierarchy]` table as it is.
template <class Mesh>
Report detail(Mesh& mesh, const std::string& recipe_toml, bool no_self_intersections = true) {
  return detail(mesh, recipe_toml, HierarchySettings{}, no_self_intersections);
}

/// asperity's version.
inline std::string version() { return std::string(ffi::version()); }

}  // namespace asperity
