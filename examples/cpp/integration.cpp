// asperity in a C++ geometry stack: what an integrator needs around the pipeline.
//
//   integration [OUT_DIR]
//
//  1. progress and cancellation: a function watching a build and a refinement, stopping
//     them (asperity::Cancelled), its own exception arriving unchanged;
//  2. asperity::validate (asperity info's report) and asperity::hausdorff;
//  3. an OpenMesh PolyMesh (quads) taken as input, triangulated as the file readers do;
//  4. analyze on a const mesh; asperity:* properties persistent through OpenMesh's .om;
//  5. threads: builds side by side, and refinements of one shared hierarchy;
//  6. a normal displacement at every level, written for the Python package's test to
//     compare with its own numpy operator bit for bit (OUT_DIR/normal-displacement.*);
//  7. a recipe setting every key of its [hierarchy] table, written with its input and
//     result for the Python package's test to run through Python and the command line and
//     compare bit for bit (OUT_DIR/recipe-every-key.*).
// Exit code 0 when everything behaved. Built with CMake (find_package) and with
// pkg-config against the shared library (scripts/cpp-example.sh).
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <asperity/pipeline.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;
using Poly = OpenMesh::PolyMesh_ArrayKernelT<>;

/// Double-precision points, so that results compare bit for bit with Python's float64.
struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using MeshD = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

struct Failed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

static void expect(bool ok, const std::string& what) {
  if (!ok) throw Failed(what);
}

/// A UV sphere of quads (triangles at the poles) as a PolyMesh.
static Poly quad_sphere(int rings, int segments) {
  Poly mesh;
  const double pi = std::acos(-1.0);
  std::vector<Poly::VertexHandle> grid;
  const auto top = mesh.add_vertex({0, 0, 1});
  for (int r = 1; r < rings; ++r) {
    const double theta = pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * pi * s / segments;
      grid.push_back(mesh.add_vertex({std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)}));
    }
  }
  const auto bottom = mesh.add_vertex({0, 0, -1});
  auto at = [&](int r, int s) { return grid[std::size_t((r - 1) * segments + (s % segments))]; };
  for (int s = 0; s < segments; ++s) mesh.add_face(top, at(1, s), at(1, s + 1));
  for (int r = 1; r + 1 < rings; ++r) {
    for (int s = 0; s < segments; ++s) mesh.add_face({at(r, s), at(r + 1, s), at(r + 1, s + 1), at(r, s + 1)});
  }
  for (int s = 0; s < segments; ++s) mesh.add_face(bottom, at(rings - 1, s + 1), at(rings - 1, s));
  return mesh;
}

/// The same sphere as triangles (each quad split along its first diagonal), for the tests
/// below that want a TriMesh.
static Mesh tri_sphere() {
  Mesh out;
  const Poly quads = quad_sphere(24, 48);
  for (auto v : quads.vertices()) out.add_vertex(Mesh::Point(quads.point(v)));
  for (auto f : quads.faces()) {
    std::vector<Mesh::VertexHandle> c;
    for (auto v : quads.fv_range(f)) c.push_back(out.vertex_handle(std::uint32_t(v.idx())));
    for (std::size_t k = 1; k + 1 < c.size(); ++k) out.add_face(c[0], c[k], c[k + 1]);
  }
  return out;
}

/// 1. Progress and cancellation.
static void progress_and_cancellation(const Mesh& input) {
  asperity::HierarchyOptions options;
  options.target_vertices = input.n_vertices() / 20;
  std::size_t reports = 0;
  options.progress = [&](const std::string&, std::uint64_t done, std::uint64_t total) {
    expect(done <= total, "progress reports done <= total");
    ++reports;
    return true;
  };
  const asperity::Hierarchy<Mesh> watched(input, options);
  expect(reports >= 3, "the build reports its progress");

  std::size_t calls = 0;
  options.progress = [&](const std::string&, std::uint64_t, std::uint64_t) { return ++calls < 3; };
  try {
    asperity::Hierarchy<Mesh> stopped(input, options);
    expect(false, "a progress function returning false stops the build");
  } catch (const asperity::Cancelled& e) {
    std::cout << "build cancelled: " << e.what() << "\n";
  }
  expect(calls == 3, "the build stopped at the report that said stop");

  options.progress = [](const std::string&, std::uint64_t, std::uint64_t) -> bool {
    throw std::domain_error("the GUI closed");
  };
  try {
    asperity::Hierarchy<Mesh> thrown(input, options);
    expect(false, "the progress function's exception stops the build");
  } catch (const std::domain_error& e) {
    expect(std::string(e.what()) == "the GUI closed", "the progress function's exception arrives unchanged");
  }

  std::vector<std::uint64_t> levels;
  watched.refine([](asperity::LevelView&) {}, nullptr,
                 [&](const std::string& stage, std::uint64_t done, std::uint64_t) {
                   expect(stage == "refine", "refinement reports as refine");
                   levels.push_back(done);
                   return true;
                 });
  expect(levels.size() + 1 == watched.level_count(), "one report per refined level");
  try {
    watched.refine([](asperity::LevelView&) {}, nullptr,
                   [](const std::string&, std::uint64_t done, std::uint64_t) { return done < 2; });
    expect(false, "a refinement stops when its progress function says so");
  } catch (const asperity::Cancelled& e) {
    std::cout << "refinement cancelled: " << e.what() << "\n";
  }
  try {
    watched.refine_region(std::vector<bool>(input.n_vertices(), true), 0, nullptr,
                          [](const std::string&, std::uint64_t, std::uint64_t) { return false; });
    expect(false, "a region refinement stops when its progress function says so");
  } catch (const asperity::Cancelled&) {
  }
  std::cout << "progress: " << reports << " build reports, " << levels.size() << " refinement reports\n";
}

/// 2. The validation report and the Hausdorff distance.
static void validate_and_measure(const Mesh& input) {
  const std::string report = asperity::validate(input);
  expect(report.find("\"genus\":0") != std::string::npos, "validate reports the sphere's genus");
  expect(asperity::hausdorff(input, input) < 1e-9, "a mesh is at distance 0 from itself");
  Mesh base = input;
  asperity::simplify(base, input.n_vertices() / 10);
  const double d = asperity::hausdorff(input, base);
  expect(d > 0.0 && d < 0.05, "the base domain is near the input");
  std::cout << "validate: " << report.substr(0, 60) << "…; hausdorff to the base " << d << "\n";
}

/// 3. A PolyMesh of quads.
static void polygon_input() {
  Poly quads = quad_sphere(12, 24);
  const std::size_t polygons = quads.n_faces();
  const std::size_t triangles_expected = 2 * 24 * (12 - 2) + 2 * 24;
  const auto a = asperity::analyze(static_cast<const Poly&>(quads));
  expect(a.k1.size() == quads.n_vertices(), "analysis of a PolyMesh covers every vertex");
  asperity::HierarchyOptions options;
  options.target_vertices = quads.n_vertices() / 4;
  const asperity::Hierarchy<Poly> h(quads, options);
  const Poly top = h.level(h.level_count() - 1);
  expect(top.n_faces() == triangles_expected, "the input's level holds each quad as two triangles");
  expect(asperity::hausdorff(quads, top) < 1e-9, "the triangulated level is the quad mesh's surface");
  asperity::simplify(quads, quads.n_vertices() / 2);
  std::cout << "PolyMesh: " << polygons << " faces as " << top.n_faces() << " triangles, simplified to "
            << quads.n_vertices() << " vertices\n";
}

/// 4. analyze on a const mesh leaves it unchanged; the properties it adds to a mutable one
/// survive OpenMesh's .om writer.
static void const_analysis_and_persistent_properties(const Mesh& input, const std::string& out) {
  const Mesh& fixed = input;
  const asperity::Analysis a = asperity::analyze(fixed);
  expect(!OpenMesh::hasProperty<OpenMesh::VertexHandle, double>(input, "asperity:k1"),
         "analyze(const Mesh&) adds no property");
  Mesh mesh = input;
  asperity::analyze(mesh);
  const std::string path = out + "/analysed.om";
  expect(OpenMesh::IO::write_mesh(mesh, path, OpenMesh::IO::Options::Custom), "write .om");
  Mesh back;
  auto k1 = OpenMesh::getOrMakeProperty<OpenMesh::VertexHandle, double>(back, "asperity:k1");
  OpenMesh::IO::Options read_options = OpenMesh::IO::Options::Custom;
  expect(OpenMesh::IO::read_mesh(back, path, read_options), "read .om");
  for (auto v : back.vertices()) expect(k1[v] == a.k1[std::size_t(v.idx())], "asperity:k1 survives the .om file");
  std::cout << "properties: asperity:k1 of " << back.n_vertices() << " vertices read back from " << path << "\n";
}

/// 5. Threads: two builds side by side equal one alone; two refinements of one hierarchy
/// side by side equal one alone.
static void threads(const Mesh& input) {
  asperity::HierarchyOptions options;
  options.target_vertices = input.n_vertices() / 20;
  const asperity::Hierarchy<Mesh> shared(input, options);
  const Mesh base = shared.level(0);
  auto bump = [](asperity::LevelView& v) {
    for (std::size_t i = 0; i < v.size(); ++i)
      for (int k = 0; k < 3; ++k) v.positions()[i][k] += 0.001 * v.normals()[i][k];
  };
  const Mesh alone = shared.refine(bump);
  Mesh built[2], refined[2];
  std::vector<std::thread> workers;
  for (int t = 0; t < 2; ++t) {
    workers.emplace_back([&, t] { built[t] = asperity::Hierarchy<Mesh>(input, options).level(0); });
    workers.emplace_back([&, t] { refined[t] = shared.refine(bump); });
  }
  for (auto& w : workers) w.join();
  for (int t = 0; t < 2; ++t) {
    expect(built[t].n_vertices() == base.n_vertices(), "a build beside another equals one alone");
    for (auto v : base.vertices()) expect(built[t].point(v) == base.point(v), "same base positions");
    for (auto v : alone.vertices()) expect(refined[t].point(v) == alone.point(v), "same refinement");
  }
  std::cout << "threads: 2 builds and 2 refinements of one hierarchy side by side, equal to one alone\n";
}

template <class T>
static void write_raw(const std::string& path, const std::vector<T>& values) {
  std::ofstream file(path, std::ios::binary);
  file.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(T)));
  expect(bool(file), "write " + path);
}

/// `single` with double-precision points (the same vertices and faces, in order).
static MeshD with_double_points(const Mesh& single) {
  MeshD input;
  for (auto v : single.vertices()) input.add_vertex(MeshD::Point(single.point(v)[0], single.point(v)[1], single.point(v)[2]));
  for (auto f : single.faces()) {
    std::vector<MeshD::VertexHandle> c;
    for (auto v : single.fv_range(f)) c.push_back(input.vertex_handle(std::uint32_t(v.idx())));
    input.add_face(c);
  }
  return input;
}

/// 6. Every level displaced along its normals by 0.002 (level + 1), the same operator as
/// python/tests/test_refine_operator.py's; the input and the result as raw little-endian
/// arrays (float64 positions in input order, uint32 triangles).
static void normal_displacement_for_python(const Mesh& single, const std::string& out) {
  const MeshD input = with_double_points(single);
  asperity::HierarchyOptions options;
  options.target_vertices = input.n_vertices() / 20;
  options.keep_features = "none";
  const asperity::Hierarchy<MeshD> h(input, options);
  MeshD result = h.refine([](asperity::LevelView& v) {
    const double step = 0.002 * double(v.level() + 1);
    for (std::size_t i = 0; i < v.size(); ++i)
      for (int k = 0; k < 3; ++k) v.positions()[i][k] += step * v.normals()[i][k];
  });
  std::vector<double> in_positions, out_positions(3 * input.n_vertices());
  std::vector<std::uint32_t> triangles;
  asperity::to_arrays(input, in_positions, triangles);
  auto id = OpenMesh::getProperty<OpenMesh::VertexHandle, int>(result, "asperity:id");
  for (auto v : result.vertices()) {
    const auto p = result.point(v);
    for (int k = 0; k < 3; ++k) out_positions[3 * std::size_t(id[v]) + std::size_t(k)] = p[k];
  }
  write_raw(out + "/normal-displacement.input-positions.f64", in_positions);
  write_raw(out + "/normal-displacement.input-triangles.u32", triangles);
  write_raw(out + "/normal-displacement.result-positions.f64", out_positions);
  std::cout << "normal displacement: " << h.level_count() << " levels, written for Python's comparison\n";
}

/// 8. A partitioned build (#40, the command line's --chunks): the target reached, every
/// level kept (made by refinement) and the round trip exact; the input and the base as
/// raw arrays for python/tests/test_asperity.py, which builds it in Python and on the
/// command line and finds the same base.
static void partitioned_for_python(const Mesh& single, const std::string& out) {
  const MeshD input = with_double_points(single);
  asperity::HierarchyOptions options;
  options.target_vertices = input.n_vertices() / 20;
  options.keep_features = "none";
  options.chunks = 3;
  const asperity::Hierarchy<MeshD> h(input, options);
  const MeshD base = h.level(0);
  expect(base.n_vertices() == *options.target_vertices, "a partitioned build reaches its target");
  expect(h.level(h.level_count() - 1).n_faces() == input.n_faces(), "its top level is the input");
  const MeshD refined = h.refine([](asperity::LevelView&) {});
  expect(refined.n_faces() == input.n_faces(), "its refinement restores every face");
  std::vector<double> in_positions, base_positions;
  std::vector<std::uint32_t> in_triangles, base_triangles;
  asperity::to_arrays(input, in_positions, in_triangles);
  asperity::to_arrays(base, base_positions, base_triangles);
  write_raw(out + "/partitioned.input-positions.f64", in_positions);
  write_raw(out + "/partitioned.input-triangles.u32", in_triangles);
  write_raw(out + "/partitioned.base-positions.f64", base_positions);
  write_raw(out + "/partitioned.base-triangles.u32", base_triangles);
  options.levels = 3;
  bool refused = false;
  try {
    const asperity::Hierarchy<MeshD> limited(input, options);
  } catch (const asperity::InputError& e) {
    refused = std::string(e.what()).find("option .chunks = 3 takes no level limit yet") != std::string::npos;
  }
  expect(refused, "chunks beside a level limit is refused, naming both");
  std::cout << "partitioned build: 3 chunks, " << h.level_count() << " levels, " << base.n_vertices()
            << " base vertices, written for Python's comparison\n";
}

/// 7. A recipe whose [hierarchy] table sets every key to a value other than its default
/// (#38: the library's one reading of the table, which the command line, Python and C++
/// all call), run by asperity::detail on the sphere with its bottom cut flat (a crease, so
/// that keep_features matters); its input, text and result as raw arrays for
/// python/tests/test_asperity.py.
static void recipe_for_python(const Mesh& single, const std::string& out) {
  const std::string recipe = R"(# Every key of [hierarchy] set (examples/cpp/integration.cpp).
seed = 5

[hierarchy]
target_vertices = "8%"
levels = 12
max_error = 0.03
keep_features = "all"
feature_vertices = "keep"
removal_weight = 0.6
swap_weight = 0.4
intersection_guard = false

[[step]]
op = "noise"
level = -2

[step.noise]
kind = "perlin"
amplitude = 0.01
frequency = 6.0
)";
  MeshD mesh = with_double_points(single);
  for (auto v : mesh.vertices()) mesh.point(v)[2] = std::max(mesh.point(v)[2], -0.6);
  std::vector<double> in_positions, out_positions;
  std::vector<std::uint32_t> in_triangles, out_triangles;
  asperity::to_arrays(mesh, in_positions, in_triangles);
  const asperity::Report report = asperity::detail(mesh, recipe);
  asperity::to_arrays(mesh, out_positions, out_triangles);
  expect(out_positions != in_positions, "the recipe moved nothing");
  write_raw(out + "/recipe-every-key.input-positions.f64", in_positions);
  write_raw(out + "/recipe-every-key.input-triangles.u32", in_triangles);
  write_raw(out + "/recipe-every-key.result-positions.f64", out_positions);
  write_raw(out + "/recipe-every-key.result-triangles.u32", out_triangles);
  std::ofstream(out + "/recipe-every-key.toml") << recipe;
  std::cout << "recipe with every [hierarchy] key: " << report.levels << " levels, " << mesh.n_vertices()
            << " vertices, written for Python's comparison\n";
}

int main(int argc, char** argv) {
  const std::string out = argc > 1 ? argv[1] : ".";
  try {
    const Mesh input = tri_sphere();
    progress_and_cancellation(input);
    validate_and_measure(input);
    polygon_input();
    const_analysis_and_persistent_properties(input, out);
    threads(input);
    normal_displacement_for_python(input, out);
    recipe_for_python(input, out);
    partitioned_for_python(input, out);
  } catch (const Failed& e) {
    std::cerr << "failed: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "asperity failed: " << e.what() << "\n";
    return 1;
  }
  std::cout << "integration: every check passed\n";
  return 0;
}
