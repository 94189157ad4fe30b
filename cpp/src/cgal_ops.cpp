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

#include <CGAL/AABB_triangle_primitive.h>
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
      throw NativeError("triangle pairs: inconsistent array lengths");
  }

  /// Triangle t: t < kept count names a kept triangle, the rest added ones. Throws for an
  /// index out of range, a corner out of range or a non-finite corner.
  const std::uint32_t* corners(std::size_t t) const {
    const std::size_t nk = kept_.n_indices / 3, na = added_.n_indices / 3;
    if (t >= nk + na) {
      std::ostringstream msg;
      msg << "triangle pairs: triangle " << t << " of " << nk + na;
      throw NativeError(msg.str());
    }
    const std::uint32_t* c = t < nk ? kept_.tris + 3 * t : added_.tris + 3 * (t - nk);
    for (int i = 0; i < 3; ++i) {
      const std::size_t v = c[i];
      const double* p = kept_.xyz + 3 * v;
      if (v >= kept_.n_coords / 3 || !std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
        std::ostringstream msg;
        msg << "triangle pairs: triangle " << t << " names vertex " << v
            << (v >= kept_.n_coords / 3 ? ", out of range" : ", which has a non-finite coordinate");
        throw NativeError(msg.str());
      }
    }
    return c;
  }
  Point point(std::uint32_t v) const {
    const double* p = kept_.xyz + 3 * static_cast<std::size_t>(v);
    return Point(p[0], p[1], p[2]);
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
    const Kernel::Triangle_3 ta(point(a[0]), point(a[1]), point(a[2]));
    const Kernel::Triangle_3 tb(point(b[0]), point(b[1]), point(b[2]));
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

}  // namespace

std::vector<std::uint8_t> triangle_pairs_intersect(const TriangleArrays& kept, const TriangleArrays& added,
                                                   const std::uint32_t* pairs, std::size_t n_values) {
  if (n_values % 2 != 0) throw NativeError("triangle pairs: the pair list has an odd length");
  const IndexedTriangles triangles(kept, added);
  std::vector<std::uint8_t> out(n_values / 2);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = triangles.intersect(pairs[2 * i], pairs[2 * i + 1]) ? 1 : 0;
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
  // The predicate stops once fewer edges than its threshold remain: one above the target
  // count stops at the target instead of one collapse past it.
  SMS::Count_stop_predicate<SurfaceMesh> stop(static_cast<std::size_t>(std::max<long long>(edges + 1, 0)));
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

struct DistanceTree::Tree {
  using Triangles = std::vector<Kernel::Triangle_3>;
  using Primitive = CGAL::AABB_triangle_primitive<Kernel, Triangles::const_iterator>;
  using Aabb = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  Triangles triangles;
  Aabb aabb;
};

DistanceTree::DistanceTree(const TriangleArrays& mesh) : tree_(std::make_unique<Tree>()) {
  if (mesh.n_coords % 3 != 0 || mesh.n_indices % 3 != 0)
    throw NativeError("distance tree: array lengths are not multiples of 3");
  const std::size_t nv = mesh.n_coords / 3, nf = mesh.n_indices / 3;
  if (nf == 0) throw NativeError("distance tree: the mesh has no faces");
  auto corner = [&](std::size_t f, int k) {
    const std::uint32_t v = mesh.tris[3 * f + k];
    if (v >= nv) {
      std::ostringstream msg;
      msg << "distance tree: face " << f << " refers to vertex " << v << " of " << nv;
      throw NativeError(msg.str());
    }
    const double* p = mesh.xyz + 3 * v;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      std::ostringstream msg;
      msg << "distance tree: vertex " << v << " has a non-finite coordinate";
      throw NativeError(msg.str());
    }
    return Point(p[0], p[1], p[2]);
  };
  tree_->triangles.reserve(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const std::uint32_t* t = mesh.tris + 3 * f;
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      std::ostringstream msg;
      msg << "distance tree: face " << f << " (" << t[0] << ", " << t[1] << ", " << t[2] << ") is degenerate";
      throw NativeError(msg.str());
    }
    tree_->triangles.emplace_back(corner(f, 0), corner(f, 1), corner(f, 2));
  }
  tree_->aabb.insert(tree_->triangles.cbegin(), tree_->triangles.cend());
  tree_->aabb.build();
  tree_->aabb.accelerate_distance_queries();
}

DistanceTree::~DistanceTree() = default;

std::vector<double> DistanceTree::distances(const double* xyz, std::size_t n_coords, bool chained) const {
  if (n_coords % 3 != 0) throw NativeError("distance tree: point array length is not a multiple of 3");
  std::vector<double> out(n_coords / 3);
  // Chained, each query starts from the closest point of the one before (a batch's points
  // are near one another: a face's samples, then its neighbour's), which spares the search
  // for a starting point; the traversal still finds the closest point.
  Point hint;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Point query(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    hint = i == 0 || !chained ? tree_->aabb.closest_point(query) : tree_->aabb.closest_point(query, hint);
    out[i] = std::sqrt(CGAL::to_double(CGAL::squared_distance(query, hint)));
  }
  return out;
}

}  // namespace asperity
