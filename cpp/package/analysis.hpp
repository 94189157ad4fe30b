// asperity::analyze: normals, curvatures and feature classes (thesis §4.4.1) of an
// OpenMesh triangle mesh, as a struct and as vertex properties of the mesh.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "asperity/fields.hpp"
#include "asperity/mesh_arrays.hpp"

namespace asperity {

/// Feature classes (thesis Algorithm 1).
enum class FeatureClass : std::uint8_t { Face = 0, Weak = 1, StrongEdge = 2, Corner = 3 };

/// Per-vertex surface analysis: unit normals, mean and Gaussian curvature, principal
/// curvatures k1 ≥ k2, feature classes.
struct Analysis {
  std::vector<Vec3> normals;
  std::vector<double> mean_curvature;
  std::vector<double> gaussian_curvature;
  std::vector<double> k1;
  std::vector<double> k2;
  std::vector<FeatureClass> feature_class;
};

/// The analysis settings (`asperity analyze`'s flags; the library's AnalysisRequest); an
/// unset one takes the library's default.
struct AnalysisOptions {
  /// Vertex normal weights (eq. 3.2): "angle" (the default), "area" or "uniform".
  std::optional<std::string> normals;
  /// Algorithm 1's thresholds on the voting tensor's normalised eigenvalues, 0 to 1: a
  /// corner when λ3 exceeds `corner` (0.1), a face vertex when λ2 is below `face` (0.02),
  /// a strong edge when λ2 exceeds `strong` (0.1).
  std::optional<double> corner;
  std::optional<double> face;
  std::optional<double> strong;
};

namespace impl {

/// The options as the library's analysis request.
inline std::string analysis_fields(const AnalysisOptions& o) {
  Fields f;
  f.add("normals", o.normals).add("corner", o.corner).add("face", o.face).add("strong", o.strong);
  return f.json();
}

inline Analysis analysis_of(const ffi::Analysis& a) {
  Analysis out;
  out.normals = vectors(a.normals);
  out.mean_curvature.assign(a.mean_curvature.begin(), a.mean_curvature.end());
  out.gaussian_curvature.assign(a.gaussian_curvature.begin(), a.gaussian_curvature.end());
  out.k1.assign(a.k1.begin(), a.k1.end());
  out.k2.assign(a.k2.begin(), a.k2.end());
  for (auto c : a.feature_class) out.feature_class.push_back(FeatureClass(c));
  return out;
}

}  // namespace impl

/// Analyses `mesh` (asperity analyze) without changing it: normals, curvatures and feature
/// classes per vertex.
template <class Mesh>
Analysis analyze(const Mesh& mesh, const AnalysisOptions& options = AnalysisOptions()) {
  std::vector<double> p;
  std::vector<std::uint32_t> t;
  to_arrays(mesh, p, t);
  const auto fields = impl::analysis_fields(options);
  return impl::analysis_of(impl::call([&] { return ffi::analyze(impl::slice(p), impl::slice(t), fields); }));
}

/// Analyses `mesh` and adds the results to it as persistent vertex properties (OpenMesh's
/// .om writer keeps them): "asperity:mean_curvature", "asperity:gaussian_curvature",
/// "asperity:k1", "asperity:k2" (double) and "asperity:feature_class" (int, FeatureClass's
/// values); the mesh's vertex normals are set too when it has them. Returns the same
/// values. (A const mesh gets the values only: the overload above.)
template <class Mesh>
Analysis analyze(Mesh& mesh, const AnalysisOptions& options = AnalysisOptions()) {
  Analysis a = analyze(static_cast<const Mesh&>(mesh), options);
  auto mean = impl::vertex_property<double>(mesh, "asperity:mean_curvature");
  auto gauss = impl::vertex_property<double>(mesh, "asperity:gaussian_curvature");
  auto k1 = impl::vertex_property<double>(mesh, "asperity:k1");
  auto k2 = impl::vertex_property<double>(mesh, "asperity:k2");
  auto cls = impl::vertex_property<int>(mesh, "asperity:feature_class");
  for (auto v : mesh.vertices()) {
    const auto i = std::size_t(v.idx());
    mean[v] = a.mean_curvature[i];
    gauss[v] = a.gaussian_curvature[i];
    k1[v] = a.k1[i];
    k2[v] = a.k2[i];
    cls[v] = int(a.feature_class[i]);
    if (mesh.has_vertex_normals()) {
      mesh.set_normal(v, typename Mesh::Normal(a.normals[i][0], a.normals[i][1], a.normals[i][2]));
    }
  }
  return a;
}

}  // namespace asperity
