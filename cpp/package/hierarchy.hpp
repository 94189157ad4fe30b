// asperity::Hierarchy: the 4-k mesh hierarchy of an OpenMesh triangle mesh (thesis §4.4,
// §4.6) — its levels as meshes, the parametrization of every vertex, refinement back to
// full resolution with a C++ operator run at every level (the thesis' D(VS, l, f),
// eq. 4.4, with f written in C++), and region refinement.
//
//   asperity::Hierarchy<Mesh> h(mesh);                 // options: HierarchyOptions
//   Mesh base = h.level(0);                            // "asperity:id" on each vertex
//   Mesh out = h.refine([](asperity::LevelView& v) {   // at every level, base first
//     if (v.level() == 2) for (auto& p : v.positions()) p[2] += 0.01;
//   });
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "asperity/analysis.hpp"
#include "asperity/mesh_arrays.hpp"
#include "asperity/progress.hpp"

namespace asperity {

/// The options of a hierarchy build (the library's SimplifyOptions; the command line's
/// `simplify` flags). Simplification stops at the first limit reached, or when a level
/// can remove nothing more. A default-made struct holds the library's defaults.
struct HierarchyOptions {
  /// Stop at this many vertices: 1 to the mesh's count (more, or 0, is an InputError, as
  /// the command line's --target-vertices).
  std::optional<std::size_t> target_vertices;
  /// Stop after this many levels.
  std::optional<std::size_t> levels;
  /// Never remove a vertex whose error exceeds this share of the bounding-box diagonal.
  std::optional<double> max_error;
  /// Feature vertices kept: "none", "corners" (thesis Fig. 5.15), "strong" (the thesis' choice) or "all".
  std::string keep_features;
  /// "along-lines" (feature-line vertices removed along their line) or "keep" (refused with
  /// keep_features "none", where no vertex is a feature).
  std::string feature_vertices;
  /// Input vertices never removed.
  std::vector<std::uint32_t> keep_vertices;
  /// Weights of the removal and swap errors in E(v) (eq. 4.1).
  double removal_weight;
  double swap_weight;
  /// Algorithm 3's angle threshold, degrees.
  double fix_threshold_degrees;
  /// Leave out the clusters whose new faces would cut the surface.
  bool intersection_guard;
  /// Build in this many parts along the Morton curve of the faces, in parallel, their
  /// borders fenced, then continue on their joined bases (the command line's --chunks;
  /// needs target_vertices or max_error, takes no levels). Empty: one piece.
  std::optional<std::size_t> chunks;
  /// Watches the build (stage, done, total); returning false stops it with
  /// asperity::Cancelled. Empty: unwatched.
  ProgressFunction progress;

  HierarchyOptions() {
    const auto d = ffi::default_hierarchy_options();
    keep_features = std::string(d.keep_features);
    feature_vertices = std::string(d.feature_vertices);
    removal_weight = d.removal_weight;
    swap_weight = d.swap_weight;
    fix_threshold_degrees = d.fix_threshold_degrees;
    intersection_guard = d.intersection_guard;
  }
};

/// Per input vertex: the level at which it appears (0: the base domain), its face in the
/// base domain (an index into level(0)'s faces; −1 for a vertex on no face) and its
/// barycentric coordinates in that face's corner order (base vertices sit on a corner).
struct Parametrization {
  std::vector<std::uint32_t> level;
  std::vector<std::int64_t> base_face;
  std::vector<Vec3> barycentric;
};

/// One refinement level as a C++ operator sees it: the level's vertices (positions
/// writable; later levels insert their vertices on the moved surface, thesis §4.5.1),
/// triangles, each vertex's input id, unit normals, the level at which each vertex first
/// appears, and on demand curvatures and feature classes.
class LevelView {
 public:
  /// Refinement level: 0 is the base domain, level_count() − 1 the input's.
  std::size_t level() const { return level_; }
  std::size_t level_count() const { return level_count_; }
  /// Vertices of this level.
  std::size_t size() const { return positions_.size(); }
  std::vector<Vec3>& positions() { return positions_; }
  const std::vector<Vec3>& positions() const { return positions_; }
  const std::vector<Triangle>& triangles() const { return triangles_; }
  /// Input vertex index of each vertex.
  const std::vector<std::uint32_t>& ids() const { return ids_; }
  /// Unit (angle-weighted) normals of the level as given, before any move.
  const std::vector<Vec3>& normals() const { return normals_; }
  /// The level at which each vertex first appears (0: a base vertex).
  const std::vector<std::uint32_t>& vertex_levels() const { return vertex_levels_; }
  /// Curvatures and feature classes of the level as given (computed on first use).
  const Analysis& analysis() {
    if (!analysis_) analysis_ = impl::analysis_of(impl::call([&] { return session_->view_analysis(); }));
    return *analysis_;
  }

  explicit LevelView(ffi::Refinement& session, std::size_t level_count) : session_(&session), level_count_(level_count) {
    const auto view = impl::call([&] { return session.view(); });
    level_ = session.current_level();
    positions_ = impl::vectors(view.level.mesh.positions);
    const auto& t = view.level.mesh.triangles;
    for (std::size_t i = 0; i + 2 < t.size(); i += 3) triangles_.push_back({t[i], t[i + 1], t[i + 2]});
    ids_.assign(view.level.ids.begin(), view.level.ids.end());
    normals_ = impl::vectors(view.normals);
    vertex_levels_.assign(view.vertex_levels.begin(), view.vertex_levels.end());
  }

  /// Hands the (possibly moved) positions back to the refinement.
  void commit() {
    std::vector<double> flat;
    flat.reserve(3 * positions_.size());
    for (const auto& p : positions_) flat.insert(flat.end(), p.begin(), p.end());
    impl::call([&] { session_->set_positions(impl::slice(flat)); });
  }

 private:
  ffi::Refinement* session_;
  std::size_t level_ = 0;
  std::size_t level_count_;
  std::vector<Vec3> positions_;
  std::vector<Triangle> triangles_;
  std::vector<std::uint32_t> ids_;
  std::vector<Vec3> normals_;
  std::vector<std::uint32_t> vertex_levels_;
  std::optional<Analysis> analysis_;
};

/// The 4-k hierarchy of a triangle mesh, every level recorded.
template <class Mesh>
class Hierarchy {
 public:
  /// Builds the hierarchy of `mesh` (throws InputError for a mesh or option asperity
  /// cannot use). Its texture coordinates (halfedge texcoords, else vertex texcoords) are
  /// carried to every level: seams are simplified along themselves, and each level's face
  /// takes its corners' UVs from the side of the seam it lies on.
  explicit Hierarchy(const Mesh& mesh, const HierarchyOptions& options = HierarchyOptions())
      : inner_(build(mesh, options)) {}

  /// Levels, the base domain (0) and the input (level_count() − 1) included.
  std::size_t level_count() const { return inner_->level_count(); }

  /// Level `l` as a mesh, each vertex's input index in the property "asperity:id" and, when
  /// the input had texture coordinates, halfedge texcoords.
  Mesh level(std::size_t l) const {
    return level_mesh<Mesh>(impl::call([&] { return inner_->level(l); }));
  }

  /// The parametrization of every input vertex.
  Parametrization parametrization() const {
    const auto p = impl::call([&] { return inner_->parametrization(); });
    Parametrization out;
    out.level.assign(p.level.begin(), p.level.end());
    out.base_face.assign(p.base_face.begin(), p.base_face.end());
    out.barycentric = impl::vectors(p.barycentric);
    return out;
  }

  /// Adds the parametrization to `input` (the mesh the hierarchy was built from) as vertex
  /// properties "asperity:level" (int), "asperity:base_face" (int) and
  /// "asperity:barycentric" (OpenMesh::Vec3d).
  void attach_parametrization(Mesh& input) const {
    const Parametrization p = parametrization();
    if (input.n_vertices() != p.level.size()) {
      throw InputError("attach_parametrization: the mesh has " + std::to_string(input.n_vertices()) +
                       " vertices, the hierarchy's input " + std::to_string(p.level.size()));
    }
    auto level = impl::vertex_property<int>(input, "asperity:level");
    auto face = impl::vertex_property<int>(input, "asperity:base_face");
    auto bary = impl::vertex_property<OpenMesh::Vec3d>(input, "asperity:barycentric");
    for (auto v : input.vertices()) {
      const auto i = std::size_t(v.idx());
      level[v] = int(p.level[i]);
      face[v] = int(p.base_face[i]);
      bary[v] = OpenMesh::Vec3d(p.barycentric[i][0], p.barycentric[i][1], p.barycentric[i][2]);
    }
  }

  /// Refines from the base domain back to the input's level, calling `op(LevelView&)` at
  /// every level (the base domain first, the input's level last); positions the operator
  /// writes move the level's vertices. With `region` (a flag per input vertex), levels
  /// after the base insert only the marked vertices. An exception the operator throws
  /// propagates unchanged (it never enters Rust). Returns the result, "asperity:id" on
  /// each vertex, with halfedge texcoords when the input had texture coordinates and every
  /// face's side of the seams is found (a vertex Algorithm 2's search placed off its seam
  /// leaves them out: the result then has none).
  /// `progress`, when set, is called after each refined level ("refine", level, levels
  /// to go through); returning false stops with asperity::Cancelled.
  template <class Operator>
  Mesh refine(Operator&& op, const std::vector<bool>* region = nullptr, const ProgressFunction& progress = {}) const {
    auto session = impl::call([&] { return ffi::start_refinement(*inner_); });
    const std::vector<std::uint8_t> inside = region ? impl::bytes(*region) : std::vector<std::uint8_t>();
    const std::uint64_t steps = level_count() - 1;
    while (true) {
      LevelView view(*session, level_count());
      op(view);
      view.commit();
      if (session->finished()) break;
      impl::call([&] { session->refine_next(impl::slice(inside)); });
      const std::uint64_t done = session->current_level();
      if (progress && !progress("refine", done, steps)) {
        throw Cancelled("cancelled by the progress callback at refine (" + std::to_string(done) + " of " +
                        std::to_string(steps) + ")");
      }
    }
    return level_mesh<Mesh>(impl::call([&] { return session->result(); }));
  }

  /// Refines the whole hierarchy up to `base_level`, then only the vertices `inside` marks
  /// (a flag per input vertex) and what they need, up to the input's level (thesis §4.6):
  /// a conforming mesh, fine in the region and coarse elsewhere. `missing`, when given,
  /// receives the region vertices no edge could take.
  /// `progress` watches it as it does the build.
  Mesh refine_region(const std::vector<bool>& inside, std::size_t base_level = 0,
                     std::vector<std::uint32_t>* missing = nullptr, const ProgressFunction& progress = {}) const {
    const auto mask = impl::bytes(inside);
    const ffi::ProgressCallback watch(progress);
    const auto out =
        impl::call(watch, [&] { return inner_->refine_region(impl::slice(mask), base_level, watch); });
    if (missing) missing->assign(out.missing.begin(), out.missing.end());
    return level_mesh<Mesh>(out.level);
  }

  /// The build's report: input and base vertices, levels, seconds.
  Report report() const { return inner_->report(); }
  /// The build's whole report as JSON, `simplify --json`'s fields: counts, the Hausdorff
  /// distance to the input, triangle shapes, and "target" (reached, what gave way, what
  /// stopped the build), measured on this call.
  std::string report_json() const { return std::string(impl::call([&] { return inner_->report_json(); })); }
  /// Build time by stage, as JSON.
  std::string stages_json() const { return std::string(inner_->stages_json()); }

 private:
  static rust::Box<ffi::BuiltHierarchy> build(const Mesh& mesh, const HierarchyOptions& o) {
    std::vector<double> p;
    std::vector<std::uint32_t> t;
    std::vector<typename Mesh::FaceHandle> faces;  // each triangle's face (a polygon's several)
    to_arrays(mesh, p, t, &faces);
    ffi::HierarchyOptions f = ffi::default_hierarchy_options();
    f.has_target_vertices = o.target_vertices.has_value();
    f.target_vertices = o.target_vertices.value_or(0);
    f.has_levels = o.levels.has_value();
    f.levels = o.levels.value_or(0);
    f.has_max_error = o.max_error.has_value();
    f.max_error = o.max_error.value_or(0.0);
    f.keep_features = o.keep_features;
    f.feature_vertices = o.feature_vertices;
    f.keep_vertices.clear();
    for (auto v : o.keep_vertices) f.keep_vertices.push_back(v);
    f.removal_weight = o.removal_weight;
    f.swap_weight = o.swap_weight;
    f.fix_threshold_degrees = o.fix_threshold_degrees;
    f.intersection_guard = o.intersection_guard;
    f.chunks = o.chunks.value_or(0);
    const std::vector<double> uvs = corner_uvs(mesh, t, faces);
    const ffi::ProgressCallback progress(o.progress);
    return impl::call(progress, [&] {
      return ffi::build_hierarchy(impl::slice(p), impl::slice(t), impl::slice(uvs), f, progress);
    });
  }

  rust::Box<ffi::BuiltHierarchy> inner_;
};

}  // namespace asperity
