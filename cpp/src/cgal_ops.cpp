// The one CGAL translation unit: quadrics, Hausdorff distance, self-intersections.
// Kept alone because each CGAL unit costs ~20 s and ~1 GB to compile.
#include "asperity/cgal_ops.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <sstream>
#include <utility>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include "asperity/reference_decimators.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>

namespace asperity {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

/// Builds a Surface_mesh whose vertex and face indices equal the array indices. With
/// `as_soup`, a face the half-edge structure refuses (non-manifold, e.g. from a decimator
/// that does not keep manifoldness) is added on its own copies of its corners instead:
/// distance measures only need the triangles.
SurfaceMesh to_surface_mesh(const TriangleArrays& in, const char* which, bool as_soup = false) {
  if (in.n_coords % 3 != 0 || in.n_indices % 3 != 0)
    throw NativeError(std::string(which) + ": array lengths are not multiples of 3");
  const std::size_t nv = in.n_coords / 3, nf = in.n_indices / 3;
  SurfaceMesh sm;
  sm.reserve(static_cast<SurfaceMesh::size_type>(nv), static_cast<SurfaceMesh::size_type>(3 * nf),
             static_cast<SurfaceMesh::size_type>(nf));
  for (std::size_t i = 0; i < nv; ++i) {
    const double* p = in.xyz + 3 * i;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      std::ostringstream msg;
      msg << which << ": vertex " << i << " has a non-finite coordinate";
      throw NativeError(msg.str());
    }
    sm.add_vertex(Point(p[0], p[1], p[2]));
  }
  for (std::size_t f = 0; f < nf; ++f) {
    SurfaceMesh::Vertex_index v[3];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t idx = in.tris[3 * f + k];
      if (idx >= nv) {
        std::ostringstream msg;
        msg << which << ": face " << f << " refers to vertex " << idx << " of " << nv;
        throw NativeError(msg.str());
      }
      v[k] = SurfaceMesh::Vertex_index(idx);
    }
    if (sm.add_face(v[0], v[1], v[2]) != SurfaceMesh::null_face()) continue;
    if (as_soup && v[0] != v[1] && v[1] != v[2] && v[0] != v[2]) {
      SurfaceMesh::Vertex_index copy[3];
      for (int k = 0; k < 3; ++k) {
        const Point corner = sm.point(v[k]);  // a copy: add_vertex may grow the point array
        copy[k] = sm.add_vertex(corner);
      }
      sm.add_face(copy[0], copy[1], copy[2]);
      continue;
    }
    {
      std::ostringstream msg;
      msg << which << ": face " << f << " (" << v[0] << ", " << v[1] << ", " << v[2]
          << ") is degenerate or non-manifold";
      throw NativeError(msg.str());
    }
  }
  return sm;
}

}  // namespace

std::vector<double> vertex_quadrics(const TriangleArrays& mesh, double boundary_weight) {
  using Policies = CGAL::Surface_mesh_simplification::GarlandHeckbert_plane_policies<SurfaceMesh, Kernel>;
  SurfaceMesh sm = to_surface_mesh(mesh, "quadrics");
  Policies policies(sm, boundary_weight);
  policies.initialize(sm, get(CGAL::vertex_point, sm), Kernel());
  std::vector<double> out;
  out.reserve(sm.number_of_vertices() * 10);
  for (auto v : sm.vertices()) {
    const auto q = get(policies.vcm(), v);
    for (int r = 0; r < 4; ++r)
      for (int c = r; c < 4; ++c) out.push_back(q(r, c));
  }
  return out;
}

std::vector<double> quadric_errors(const double* quadrics, std::size_t n_quadric_values,
                                   const double* xyz, std::size_t n_coords) {
  if (n_quadric_values % 10 != 0 || n_coords % 3 != 0 || n_quadric_values / 10 != n_coords / 3)
    throw NativeError("quadric_errors: need one quadric (10 values) per point (3 values)");
  const std::size_t n = n_coords / 3;
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double* q = quadrics + 10 * i;
    const double h[4] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], 1.0};
    // Expand the symmetric form from its upper triangle.
    const double m[4][4] = {{q[0], q[1], q[2], q[3]},
                            {q[1], q[4], q[5], q[6]},
                            {q[2], q[5], q[7], q[8]},
                            {q[3], q[6], q[8], q[9]}};
    double e = 0.0;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) e += h[r] * m[r][c] * h[c];
    out[i] = e;
  }
  return out;
}

double symmetric_hausdorff(const TriangleArrays& a, const TriangleArrays& b,
                           double points_per_area_unit, unsigned seed) {
  const SurfaceMesh ma = to_surface_mesh(a, "hausdorff (first mesh)", true);
  const SurfaceMesh mb = to_surface_mesh(b, "hausdorff (second mesh)", true);
  if (ma.number_of_faces() == 0 || mb.number_of_faces() == 0)
    throw NativeError("hausdorff: a mesh has no faces");
  // CGAL 5.5 samples edges with its thread-local default generator (time-seeded), not
  // with random_seed: seed that one too, so the distance is the same on every run.
  CGAL::get_default_random() = CGAL::Random(seed);
  if (points_per_area_unit > 0.0) {
    return PMP::approximate_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(
        ma, mb,
        CGAL::parameters::random_seed(seed).number_of_points_per_area_unit(points_per_area_unit),
        CGAL::parameters::random_seed(seed).number_of_points_per_area_unit(points_per_area_unit));
  }
  return PMP::approximate_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(
      ma, mb, CGAL::parameters::random_seed(seed), CGAL::parameters::random_seed(seed));
}

std::vector<std::uint32_t> self_intersections(const TriangleArrays& mesh) {
  const SurfaceMesh sm = to_surface_mesh(mesh, "self-intersections");
  std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> pairs;
  PMP::self_intersections<CGAL::Sequential_tag>(sm, std::back_inserter(pairs));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> sorted;
  sorted.reserve(pairs.size());
  for (const auto& p : pairs) {
    std::uint32_t f = static_cast<std::uint32_t>(p.first), g = static_cast<std::uint32_t>(p.second);
    if (f > g) std::swap(f, g);
    sorted.emplace_back(f, g);
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::uint32_t> out;
  out.reserve(2 * sorted.size());
  for (const auto& p : sorted) out.insert(out.end(), {p.first, p.second});
  return out;
}

namespace {

/// Triangles as vertex index triples over a shared array of points, for the pair test.
class IndexedTriangles {
 public:
  IndexedTriangles(const TriangleArrays& kept, const TriangleArrays& added) : kept_(kept), added_(added) {
    if (kept.n_coords != added.n_coords || kept.n_coords % 3 != 0 || kept.n_indices % 3 != 0 ||
        added.n_indices % 3 != 0)
      throw NativeError("added-triangle intersections: inconsistent array lengths");
    const std::size_t nv = kept.n_coords / 3;
    for (const TriangleArrays* arrays : {&kept, &added})
      for (std::size_t i = 0; i < arrays->n_indices; ++i) {
        const std::uint32_t v = arrays->tris[i];
        if (v >= nv) {
          std::ostringstream msg;
          msg << "added-triangle intersections: triangle " << i / 3 << " names vertex " << v << " of " << nv;
          throw NativeError(msg.str());
        }
        const double* p = kept.xyz + 3 * static_cast<std::size_t>(v);
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
          std::ostringstream msg;
          msg << "added-triangle intersections: vertex " << v << " has a non-finite coordinate";
          throw NativeError(msg.str());
        }
      }
  }

  /// Triangle t: t < kept count names a kept triangle, the rest added ones.
  const std::uint32_t* corners(std::size_t t) const {
    const std::size_t nk = kept_.n_indices / 3;
    return t < nk ? kept_.tris + 3 * t : added_.tris + 3 * (t - nk);
  }
  Point point(std::uint32_t v) const {
    const double* p = kept_.xyz + 3 * static_cast<std::size_t>(v);
    return Point(p[0], p[1], p[2]);
  }
  CGAL::Bbox_3 bbox(std::size_t t) const {
    const std::uint32_t* c = corners(t);
    return point(c[0]).bbox() + point(c[1]).bbox() + point(c[2]).bbox();
  }

  /// Whether triangles s and t overlap beyond the vertices or edge they share (the rules of
  /// PMP::internal::do_faces_intersect, on vertex indices instead of half-edges).
  bool intersect(std::size_t s, std::size_t t) const {
    const std::uint32_t* a = corners(s);
    const std::uint32_t* b = corners(t);
    int shared = 0, ia = -1, ib = -1;  // a shared corner: a[ia] == b[ib]
    bool a_shared[3] = {false, false, false}, b_shared[3] = {false, false, false};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (a[i] == b[j]) {
          ++shared;
          a_shared[i] = b_shared[j] = true;
          ia = i;
          ib = j;
        }
    const Kernel::Triangle_3 ta(point(a[0]), point(a[1]), point(a[2]));
    const Kernel::Triangle_3 tb(point(b[0]), point(b[1]), point(b[2]));
    if (shared >= 3) return true;  // the same triangle twice
    if (shared == 2) {
      // Along the shared edge (p, q): they overlap iff coplanar with the third corners on
      // the same side of the edge.
      int ca = 0, cb = 0;
      while (a_shared[ca]) ++ca;
      while (b_shared[cb]) ++cb;
      const Point p = point(a[(ca + 1) % 3]), q = point(a[(ca + 2) % 3]);
      const Point r = point(a[ca]), s2 = point(b[cb]);
      return CGAL::coplanar(p, q, r, s2) && CGAL::coplanar_orientation(p, q, r, s2) == CGAL::POSITIVE;
    }
    if (shared == 1) {
      // Around the shared corner: they overlap iff the edge opposite it in one crosses the other.
      const Kernel::Segment_3 opposite_a(point(a[(ia + 1) % 3]), point(a[(ia + 2) % 3]));
      const Kernel::Segment_3 opposite_b(point(b[(ib + 1) % 3]), point(b[(ib + 2) % 3]));
      return CGAL::do_intersect(ta, opposite_b) || CGAL::do_intersect(tb, opposite_a);
    }
    return CGAL::do_intersect(ta, tb);
  }

 private:
  const TriangleArrays& kept_;
  const TriangleArrays& added_;
};

/// A uniform grid over boxes, its cells hashed into a table of about twice as many
/// buckets as boxes (counting-sorted): the broad phase of added_triangle_intersections.
/// Cells are about the mean box size (at least an eighth of the largest), so a box covers
/// few cells whatever the shape of the surface. A pair of boxes is reported in exactly
/// one cell, the one holding the low corner of their intersection (a box listed twice in a
/// bucket through a hash collision can repeat a pair; callers deduplicate).
class BoxGrid {
 public:
  explicit BoxGrid(const std::vector<CGAL::Bbox_3>& boxes) {
    CGAL::Bbox_3 all = boxes.front();
    double total = 0.0, largest = 0.0;
    for (const CGAL::Bbox_3& b : boxes) {
      all += b;
      const double e = std::max({b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()});
      total += e;
      largest = std::max(largest, e);
    }
    const double span = std::max({all.xmax() - all.xmin(), all.ymax() - all.ymin(), all.zmax() - all.zmin()});
    cell_ = std::max({total / static_cast<double>(boxes.size()), largest / 8.0, span / double(1 << 20), 1e-300});
    origin_ = {all.xmin(), all.ymin(), all.zmin()};
    for (int d = 0; d < 3; ++d) dims_[d] = static_cast<std::uint64_t>((all.max(d) - all.min(d)) / cell_) + 1;
    bits_ = 1;
    while ((std::size_t{1} << bits_) < 2 * boxes.size()) ++bits_;
    start_.assign((std::size_t{1} << bits_) + 1, 0);
    for (std::size_t i = 0; i < boxes.size(); ++i)
      for_cells(boxes[i], [&](std::uint64_t key) { ++start_[bucket(key) + 1]; });
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    entries_.resize(start_.back());
    for (std::size_t i = 0; i < boxes.size(); ++i)
      for_cells(boxes[i], [&](std::uint64_t key) { entries_[fill[bucket(key)]++] = static_cast<std::uint32_t>(i); });
  }

  /// Calls f(i) for every grid box i whose box overlaps `b`. A query box covering more
  /// cells than there are boxes scans the boxes instead.
  template <class F>
  void query(const CGAL::Bbox_3& b, const std::vector<CGAL::Bbox_3>& boxes, F&& f) const {
    double cells = 1.0;
    for (int d = 0; d < 3; ++d) cells *= static_cast<double>(axis_cell(d, b.max(d)) - axis_cell(d, b.min(d)) + 1);
    if (cells > static_cast<double>(boxes.size())) {
      for (std::size_t i = 0; i < boxes.size(); ++i)
        if (CGAL::do_overlap(b, boxes[i])) f(static_cast<std::uint32_t>(i));
      return;
    }
    for_cells(b, [&](std::uint64_t key) {
      const std::size_t k = bucket(key);
      for (std::uint32_t e = start_[k]; e < start_[k + 1]; ++e) {
        const std::uint32_t i = entries_[e];
        const CGAL::Bbox_3& o = boxes[i];
        if (!CGAL::do_overlap(b, o)) continue;
        const double low[3] = {std::max(b.xmin(), o.xmin()), std::max(b.ymin(), o.ymin()), std::max(b.zmin(), o.zmin())};
        if (key_of(low) == key) f(i);
      }
    });
  }

 private:
  std::uint64_t axis_cell(int d, double v) const {
    const double t = std::floor((v - origin_[d]) / cell_);
    if (!(t > 0.0)) return 0;
    return std::min(static_cast<std::uint64_t>(t), dims_[d] - 1);
  }
  std::uint64_t key_of(const double p[3]) const {
    return (axis_cell(2, p[2]) * dims_[1] + axis_cell(1, p[1])) * dims_[0] + axis_cell(0, p[0]);
  }
  std::size_t bucket(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9e3779b97f4a7c15ULL) >> (64 - bits_));
  }
  template <class F>
  void for_cells(const CGAL::Bbox_3& b, F&& f) const {
    const std::uint64_t x0 = axis_cell(0, b.xmin()), x1 = axis_cell(0, b.xmax());
    const std::uint64_t y0 = axis_cell(1, b.ymin()), y1 = axis_cell(1, b.ymax());
    const std::uint64_t z0 = axis_cell(2, b.zmin()), z1 = axis_cell(2, b.zmax());
    for (std::uint64_t z = z0; z <= z1; ++z)
      for (std::uint64_t y = y0; y <= y1; ++y)
        for (std::uint64_t x = x0; x <= x1; ++x) f((z * dims_[1] + y) * dims_[0] + x);
  }

  double cell_ = 1.0;
  std::array<double, 3> origin_{};
  std::array<std::uint64_t, 3> dims_{};
  unsigned bits_ = 1;
  std::vector<std::uint32_t> start_;
  std::vector<std::uint32_t> entries_;
};

}  // namespace

std::vector<std::uint32_t> added_triangle_intersections(const TriangleArrays& kept, const TriangleArrays& added,
                                                        bool added_pairs) {
  const IndexedTriangles triangles(kept, added);
  const std::size_t nk = kept.n_indices / 3, na = added.n_indices / 3;
  if (na == 0) return {};
  std::vector<CGAL::Bbox_3> added_boxes(na);
  for (std::size_t i = 0; i < na; ++i) added_boxes[i] = triangles.bbox(nk + i);
  const BoxGrid grid(added_boxes);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  // Added against kept: every kept triangle looks up the added ones near it.
  for (std::size_t k = 0; k < nk; ++k)
    grid.query(triangles.bbox(k), added_boxes, [&](std::uint32_t i) {
      if (triangles.intersect(k, nk + i))
        pairs.emplace_back(static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(nk + i));
    });
  // Added against added, each pair once.
  for (std::size_t i = 0; i < (added_pairs ? na : 0); ++i)
    grid.query(added_boxes[i], added_boxes, [&](std::uint32_t j) {
      if (j > i && triangles.intersect(nk + i, nk + j))
        pairs.emplace_back(static_cast<std::uint32_t>(nk + i), static_cast<std::uint32_t>(nk + j));
    });
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  std::vector<std::uint32_t> out;
  out.reserve(2 * pairs.size());
  for (const auto& p : pairs) out.insert(out.end(), {p.first, p.second});
  return out;
}

DecimatedArrays cgal_decimate(const TriangleArrays& mesh, std::size_t target_vertices) {
  namespace SMS = CGAL::Surface_mesh_simplification;
  SurfaceMesh sm = to_surface_mesh(mesh, "CGAL edge_collapse");
  // V - E + F = chi and 2E = 3F + boundary edges: E = 3V - 3chi + boundary edges.
  const long long v = static_cast<long long>(sm.number_of_vertices());
  const long long e = static_cast<long long>(sm.number_of_edges());
  const long long f = static_cast<long long>(sm.number_of_faces());
  long long boundary = 0;
  for (auto h : sm.halfedges()) boundary += sm.is_border(h) ? 1 : 0;
  const long long chi = v - e + f;
  const long long edges = 3 * static_cast<long long>(target_vertices) - 3 * chi + boundary;
  SMS::Count_stop_predicate<SurfaceMesh> stop(static_cast<std::size_t>(std::max<long long>(edges, 0)));
  SMS::GarlandHeckbert_plane_policies<SurfaceMesh, Kernel> policies(sm);
  SMS::edge_collapse(sm, stop, CGAL::parameters::get_cost(policies.get_cost()).get_placement(policies.get_placement()));
  sm.collect_garbage();
  DecimatedArrays out;
  for (auto vi : sm.vertices()) {
    const Point& p = sm.point(vi);
    out.positions.insert(out.positions.end(), {p.x(), p.y(), p.z()});
  }
  for (auto fi : sm.faces())
    for (auto vi : CGAL::vertices_around_face(sm.halfedge(fi), sm)) out.triangles.push_back(static_cast<std::uint32_t>(vi.idx()));
  return out;
}

std::vector<double> point_distances(const double* xyz, std::size_t n_coords, const TriangleArrays& mesh) {
  if (n_coords % 3 != 0) throw NativeError("point_distances: point array length is not a multiple of 3");
  SurfaceMesh sm = to_surface_mesh(mesh, "point_distances", true);
  if (sm.number_of_faces() == 0) throw NativeError("point_distances: the mesh has no faces");
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  Tree tree(faces(sm).first, faces(sm).second, sm);
  tree.accelerate_distance_queries();
  std::vector<double> out(n_coords / 3);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = std::sqrt(CGAL::to_double(tree.squared_distance(Point(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]))));
  return out;
}

}  // namespace asperity
