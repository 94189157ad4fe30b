// asperity::terrain: fractal terrain meshes (seeds 000–003) with every parameter of
// `asperity terrain` that shapes a mesh.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include <OpenMesh/Core/Utils/color_cast.hh>

#include "asperity/errors.hpp"
#include "asperity/fields.hpp"
#include "asperity/mesh_arrays.hpp"

namespace asperity {

/// `asperity terrain`'s parameters, the library's terrain request (see `asperity terrain
/// --help`; `iterations` and `roughness` are spelled `size` and `hurst` here). Unset
/// options take the request's defaults; an option that does not apply to the method is
/// refused, naming it.
struct TerrainOptions {
  /// classic, smooth or dual.
  std::string method = "classic";
  /// Points per side, 2^n + 1 (classic, smooth).
  std::optional<std::uint64_t> size;
  /// Roughness H: the displacement scale falls by 2^-H per level.
  std::optional<double> hurst;
  /// Displacement scale at the first level.
  std::optional<double> sigma;
  /// Dual: the quadrilateral's sides, its divisions, and its variants.
  std::optional<std::array<double, 3>> x;
  std::optional<std::array<double, 3>> y;
  std::optional<std::uint32_t> levels;
  bool deterministic = false;
  bool cross_product = false;
  bool no_mean_correction = false;
  std::uint64_t seed = 0;
  /// normal, uniform, exponential or laplace; its mean and variance.
  std::optional<std::string> distribution;
  std::optional<double> mean;
  std::optional<double> variance;
  /// Corner heights x0y0, xNy0, x0yN, xNyN.
  std::optional<std::array<double, 4>> corners;
  /// Seed 001's applet variant.
  bool applet = false;
  /// World extent along x and y.
  std::optional<double> width;
  std::optional<double> depth;
  /// The highest point's height (scales every height).
  std::optional<double> max_height;
  std::optional<double> sea_level;
  /// The colour ramp: sea, low, mid, high, peak.
  std::optional<std::array<std::array<std::uint32_t, 3>, 5>> colors;
  std::optional<double> peak_height;
  /// square, triangle or hex.
  std::optional<std::string> grid;
  /// Erosion ("thermal", "hydraulic" or "thermal,hydraulic"), its iterations and talus
  /// angle in degrees.
  std::optional<std::string> erode;
  std::optional<std::uint32_t> erode_iterations;
  std::optional<double> talus;
  /// Hydraulic erosion's rain, evaporation, sediment capacity, dissolving and deposition
  /// rates and time step (`asperity terrain --rain` and the others; "hydraulic" only).
  std::optional<double> rain;
  std::optional<double> evaporation;
  std::optional<double> capacity;
  std::optional<double> dissolving;
  std::optional<double> deposition;
  std::optional<double> time_step;
  /// One tile I, J of tile_size points a side (2^k + 1).
  std::optional<std::array<std::uint64_t, 2>> tile;
  std::optional<std::uint64_t> tile_size;
};

namespace impl {

inline std::string terrain_fields(const TerrainOptions& o) {
  Fields f;
  f.add("method", o.method).add("size", o.size).add("hurst", o.hurst).add("sigma", o.sigma);
  f.add("x", o.x).add("y", o.y).add("levels", o.levels);
  if (o.deterministic) f.add("deterministic", true);
  if (o.cross_product) f.add("cross_product", true);
  if (o.no_mean_correction) f.add("no_mean_correction", true);
  f.add("seed", o.seed).add("distribution", o.distribution).add("mean", o.mean).add("variance", o.variance);
  f.add("corners", o.corners).add("width", o.width).add("depth", o.depth);
  if (o.applet) f.add("applet", true);
  f.add("max_height", o.max_height).add("sea_level", o.sea_level).add("peak_height", o.peak_height);
  f.add("colors", o.colors).add("grid", o.grid).add("erode", o.erode);
  f.add("erode_iterations", o.erode_iterations).add("talus", o.talus);
  f.add("rain", o.rain).add("evaporation", o.evaporation).add("capacity", o.capacity);
  f.add("dissolving", o.dissolving).add("deposition", o.deposition).add("time_step", o.time_step);
  f.add("tile", o.tile).add("tile_size", o.tile_size);
  return f.json();
}

}  // namespace impl

/// The terrain mesh the options describe. Vertex normals and colours are requested on the
/// mesh and set.
template <class Mesh>
Mesh terrain(const TerrainOptions& options = TerrainOptions()) {
  const auto fields = impl::terrain_fields(options);
  const auto out = impl::call([&] { return ffi::terrain_mesh(fields); });
  Mesh mesh;
  from_arrays(mesh, out.mesh);
  const bool normals = out.normals.size() == 3 * mesh.n_vertices();
  const bool colors = out.colors.size() == 3 * mesh.n_vertices();
  if (normals) mesh.request_vertex_normals();
  if (colors) mesh.request_vertex_colors();
  for (auto v : mesh.vertices()) {
    const auto i = 3 * std::size_t(v.idx());
    if (normals) mesh.set_normal(v, typename Mesh::Normal(out.normals[i], out.normals[i + 1], out.normals[i + 2]));
    if (colors) {
      mesh.set_color(v, OpenMesh::color_cast<typename Mesh::Color>(
                            OpenMesh::Vec3uc(out.colors[i], out.colors[i + 1], out.colors[i + 2])));
    }
  }
  return mesh;
}

}  // namespace asperity
