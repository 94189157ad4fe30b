// asperity from C++: a program with its own OpenMesh TriMesh uses the whole package.
//
//   openmesh_pipeline [MESH] [OUT_DIR]
//
//  1. simplify MESH (a sphere made here when none or "" is given) to a tenth of its vertices;
//  2. build its hierarchy with options, read its levels and attach the parametrization;
//  3. refine it with a C++ operator at chosen levels (normals, curvatures, vertex levels);
//  4. refine only a region, and carry texture coordinates through the levels;
//  5. analyse the mesh into OpenMesh properties, sample noise at points;
//  6. apply a detail recipe, make a terrain from an options struct;
//  7. show that bad input is an asperity::InputError and that an operator's own exception
//     comes back unchanged.
// Results are written with OpenMesh's own writer. Exit code 0 when everything behaved.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include <asperity/pipeline.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <string>

using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;

static const char* RECIPE = R"(
seed = 11

[color]
rest = [200, 190, 180]
deformed = [20, 20, 20]

[[step]]
op = "variation"
level = 1
noise = { kind = "turbulence", amplitude = 0.04, frequency = 3.0 }

[[step]]
op = "noise"
level = -1
noise = { kind = "gabor", amplitude = 0.004, frequency = 25.0 }
)";

/// A failed expectation: the program reports it and exits 1.
struct Failed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

static void expect(bool ok, const std::string& what) {
  if (!ok) throw Failed(what);
}

/// An octahedron refined by OpenMesh's Loop subdivider and pushed onto the unit sphere.
static Mesh sphere() {
  Mesh mesh;
  Mesh::VertexHandle v[6] = {
      mesh.add_vertex({1, 0, 0}), mesh.add_vertex({-1, 0, 0}), mesh.add_vertex({0, 1, 0}),
      mesh.add_vertex({0, -1, 0}), mesh.add_vertex({0, 0, 1}),  mesh.add_vertex({0, 0, -1})};
  const int faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (auto& f : faces) mesh.add_face(v[f[0]], v[f[1]], v[f[2]]);
  OpenMesh::Subdivider::Uniform::LoopT<Mesh> loop;
  loop.attach(mesh);
  loop(5);
  loop.detach();
  for (auto vh : mesh.vertices()) mesh.set_point(vh, mesh.point(vh).normalized());
  return mesh;
}

static void write(const Mesh& mesh, const std::string& path) {
  if (!OpenMesh::IO::write_mesh(mesh, path)) throw std::runtime_error("cannot write " + path);
}

static double largest_move(const Mesh& from, const Mesh& to) {
  double moved = 0;
  for (auto v : from.vertices()) moved = std::max(moved, double((to.point(v) - from.point(v)).norm()));
  return moved;
}

/// 2. The hierarchy, its levels and the parametrization as OpenMesh properties.
static void levels_and_parametrization(const asperity::Hierarchy<Mesh>& h, Mesh& input, const std::string& out) {
  const auto r = h.report();
  std::cout << "hierarchy: " << h.level_count() << " levels, " << r.input_vertices << " => " << r.output_vertices
            << " vertices in " << r.seconds << " s\n";
  expect(h.level_count() >= 3, "a hierarchy of several levels");
  // The whole report (simplify --json's): whether the target was reached, what stopped it.
  const std::string report = h.report_json();
  expect(report.find("\"reached\":true") != std::string::npos, "the report says the target was reached");
  expect(report.find("\"hausdorff\":") != std::string::npos, "the report measures the distance to the input");
  Mesh base = h.level(0);
  expect(base.n_vertices() == r.output_vertices, "level 0 is the base domain");
  expect(h.level(h.level_count() - 1).n_vertices() == input.n_vertices(), "the last level is the input");
  auto id = OpenMesh::getProperty<OpenMesh::VertexHandle, int>(base, "asperity:id");
  for (auto v : base.vertices()) expect(base.point(v) == input.point(input.vertex_handle(id[v])), "ids name input vertices");
  write(base, out + "/cpp-hierarchy-base.off");

  h.attach_parametrization(input);
  auto level = OpenMesh::getProperty<OpenMesh::VertexHandle, int>(input, "asperity:level");
  auto face = OpenMesh::getProperty<OpenMesh::VertexHandle, int>(input, "asperity:base_face");
  auto bary = OpenMesh::getProperty<OpenMesh::VertexHandle, OpenMesh::Vec3d>(input, "asperity:barycentric");
  std::size_t at_base = 0;
  for (auto v : input.vertices()) {
    at_base += level[v] == 0;
    expect(face[v] >= 0 && face[v] < int(base.n_faces()), "every vertex has a base face");
    expect(std::abs(bary[v][0] + bary[v][1] + bary[v][2] - 1.0) < 1e-9, "barycentrics sum to 1");
  }
  expect(at_base == base.n_vertices(), "level 0 vertices are the base domain's");
  // keep_vertices: a vertex the first hierarchy removed stays in the base when kept.
  int removed = -1;
  for (auto v : input.vertices()) {
    if (level[v] > 0) removed = v.idx();
  }
  asperity::HierarchyOptions keep;
  keep.target_vertices = input.n_vertices() / 20;
  keep.keep_features = "none";
  keep.keep_vertices = {std::uint32_t(removed)};
  Mesh kept_base = asperity::Hierarchy<Mesh>(input, keep).level(0);
  auto kept_id = OpenMesh::getProperty<OpenMesh::VertexHandle, int>(kept_base, "asperity:id");
  bool found = false;
  for (auto v : kept_base.vertices()) found |= kept_id[v] == removed;
  expect(found, "keep_vertices keeps the vertex in the base domain");
  std::cout << "parametrization: " << at_base << " base vertices, every vertex on a base face\n";
}

/// 3. A C++ operator at every level: bumps along the normal on level 1, flattened where the
/// surface curves less than average on the input's level; records what it saw.
static void refine_with_an_operator(const asperity::Hierarchy<Mesh>& h, const Mesh& input, const std::string& out) {
  std::vector<std::size_t> seen;
  std::size_t highest_appearance = 0;
  Mesh result = h.refine([&](asperity::LevelView& view) {
    seen.push_back(view.level());
    for (auto l : view.vertex_levels()) highest_appearance = std::max<std::size_t>(highest_appearance, l);
    if (view.level() == 1) {
      for (std::size_t i = 0; i < view.size(); ++i) {
        const auto& p = view.positions()[i];
        const double bump = 0.03 * std::sin(6 * p[0]) * std::cos(6 * p[1]);
        for (int k = 0; k < 3; ++k) view.positions()[i][k] += bump * view.normals()[i][k];
      }
    }
    if (view.level() + 1 == view.level_count()) {
      const auto& a = view.analysis();
      expect(a.mean_curvature.size() == view.size(), "curvature for every vertex of the level");
    }
  });
  expect(seen.size() == h.level_count() && std::is_sorted(seen.begin(), seen.end()), "the operator saw every level in order");
  expect(highest_appearance + 1 == h.level_count(), "vertex levels reach the input's level");
  expect(result.n_vertices() == input.n_vertices(), "refinement reaches full resolution");
  const double moved = largest_move(input, result);
  std::cout << "refine: operator ran on " << seen.size() << " levels, largest move " << moved << "\n";
  expect(moved > 0.005 && moved < 0.1, "the operator's bumps reach the full-resolution mesh");
  write(result, out + "/cpp-refined.off");

  // An operator's own exception comes back unchanged (it never enters Rust).
  try {
    h.refine([](asperity::LevelView& view) {
      if (view.level() == 1) throw std::logic_error("operator gave up at level 1");
    });
    expect(false, "the operator's exception propagates");
  } catch (const std::logic_error& e) {
    std::cout << "operator exception: " << e.what() << "\n";
  }
}

/// 4. Region refinement: the upper cap at full resolution, the rest at the base's.
static void refine_a_region(const asperity::Hierarchy<Mesh>& h, const Mesh& input, const std::string& out) {
  std::vector<bool> cap;
  for (auto v : input.vertices()) cap.push_back(input.point(v)[2] > 0.5);
  std::vector<std::uint32_t> missing;
  Mesh region = h.refine_region(cap, 0, &missing);
  std::cout << "region: " << region.n_vertices() << " vertices (input " << input.n_vertices() << ", base "
            << h.report().output_vertices << "), " << missing.size() << " missing\n";
  expect(region.n_vertices() < input.n_vertices() && region.n_vertices() > h.report().output_vertices,
         "the region is fine, the rest coarse");
  write(region, out + "/cpp-region.off");
}

/// 4b. Texture coordinates through the hierarchy: spherical UVs with a seam where the
/// longitude wraps (halfedge texcoords, a seam vertex has one per side); every level keeps
/// them, and no face away from the poles spans the seam.
static void textured_levels(Mesh input, const std::string& out) {
  input.request_halfedge_texcoords2D();
  for (auto f : input.faces()) {
    float u[3], v[3];
    Mesh::HalfedgeHandle hs[3];
    int k = 0;
    for (auto h : input.fh_range(f)) {
      const auto p = input.point(input.to_vertex_handle(h));
      u[k] = float(std::atan2(p[1], p[0]) / (2 * M_PI) + 0.5);
      v[k] = float(0.5 + std::asin(std::clamp(double(p[2]), -1.0, 1.0)) / M_PI);
      hs[k++] = h;
    }
    // A face across the wrap takes u + 1 on its low side: the seam.
    const float lo = std::min({u[0], u[1], u[2]}), hi = std::max({u[0], u[1], u[2]});
    for (int j = 0; j < 3; ++j) {
      if (hi - lo > 0.5f && u[j] < 0.5f) u[j] += 1.0f;
      input.set_texcoord2D(hs[j], Mesh::TexCoord2D(u[j], v[j]));
    }
  }
  asperity::HierarchyOptions options;
  options.target_vertices = input.n_vertices() / 10;
  options.keep_features = "none";
  const asperity::Hierarchy<Mesh> h(input, options);
  std::size_t checked = 0;
  for (std::size_t l = 0; l < h.level_count(); l += 3) {
    Mesh level = h.level(l);
    expect(level.has_halfedge_texcoords2D(), "every level carries the texture coordinates");
    for (auto f : level.faces()) {
      float lo = 2, hi = -1;
      bool pole = false;
      for (auto hh : level.fh_range(f)) {
        const float u = level.texcoord2D(hh)[0];
        lo = std::min(lo, u);
        hi = std::max(hi, u);
        pole |= std::abs(level.point(level.to_vertex_handle(hh))[2]) > 0.95f;
      }
      if (!pole) {
        expect(hi - lo < 0.5f, "level " + std::to_string(l) + ": a face spans the seam");
        ++checked;
      }
    }
  }
  std::cout << "texture coordinates: " << checked << " faces of " << (h.level_count() + 2) / 3
            << " levels checked, none spans the seam\n";
  OpenMesh::IO::Options with_uvs(OpenMesh::IO::Options::FaceTexCoord);
  if (!OpenMesh::IO::write_mesh(h.level(0), out + "/cpp-textured-base.obj", with_uvs)) {
    throw std::runtime_error("cannot write the textured base");
  }
}

/// 5. Analysis into properties; noise at points.
static void analysis_and_noise(Mesh input) {
  input.request_vertex_normals();
  const auto a = asperity::analyze(input);
  auto mean = OpenMesh::getProperty<OpenMesh::VertexHandle, double>(input, "asperity:mean_curvature");
  std::vector<double> h;
  for (auto v : input.vertices()) h.push_back(std::abs(mean[v]));
  std::nth_element(h.begin(), h.begin() + h.size() / 2, h.end());
  const auto faces = std::count(a.feature_class.begin(), a.feature_class.end(), asperity::FeatureClass::Face);
  std::cout << "analyze: median |H| " << h[h.size() / 2] << " on the unit sphere, " << faces << " of "
            << a.feature_class.size() << " vertices of class face\n";
  expect(std::abs(h[h.size() / 2] - 1.0) < 0.1, "a unit sphere's mean curvature is 1");
  expect(std::abs(input.normal(input.vertex_handle(0)).norm() - 1.0) < 1e-6, "vertex normals set");
  // The options reach the library's analysis request: uniform weights give other normals.
  asperity::AnalysisOptions uniform;
  uniform.normals = "uniform";
  const auto b = asperity::analyze(static_cast<const Mesh&>(input), uniform);
  expect(b.normals != a.normals, "AnalysisOptions.normals is applied");

  std::vector<asperity::Vec3> points;
  for (auto v : input.vertices()) points.push_back({input.point(v)[0], input.point(v)[1], input.point(v)[2]});
  asperity::NoiseOptions gabor;
  gabor.kind = "gabor";
  gabor.k = 2.0;
  gabor.f0 = 4.0;
  const auto values = asperity::noise(points, gabor);
  gabor.seed = 1;
  const auto other = asperity::noise(points, gabor);
  double spread = 0;
  for (double x : values) spread = std::max(spread, std::abs(x));
  std::cout << "noise: gabor at " << values.size() << " points, largest |value| " << spread << "\n";
  expect(values.size() == points.size() && spread > 0.5 && values != other, "noise values vary with the seed");
  try {
    gabor.octaves = 3;
    asperity::noise(points, gabor);
    expect(false, "an option of another noise kind is refused");
  } catch (const asperity::InputError& e) {
    std::cout << "noise option refused: " << e.what() << "\n";
    expect(std::string(e.what()).find("option .octaves applies only to") != std::string::npos,
           "the refusal names the option as C++ spells it");
  }
}

/// 6. A recipe and a terrain.
static void recipe_and_terrain(const Mesh& input, const std::string& out) {
  Mesh detailed = input;
  auto r = asperity::detail(detailed, RECIPE, true);
  const double moved = largest_move(input, detailed);
  std::cout << "detail: " << r.output_vertices << " vertices over " << r.levels << " levels, largest move " << moved << "\n";
  expect(detailed.n_vertices() == input.n_vertices() && moved > 1e-4 && std::isfinite(moved), "the recipe moved the mesh");
  expect(detailed.has_vertex_colors(), "the recipe's [color] table coloured the vertices");
  write(detailed, out + "/cpp-detail.off");

  asperity::TerrainOptions land_options;
  land_options.size = 65;
  land_options.hurst = 0.9;
  land_options.seed = 7;
  land_options.sea_level = 0.0;
  land_options.grid = "triangle";
  Mesh land = asperity::terrain<Mesh>(land_options);
  std::cout << "terrain: " << land.n_vertices() << " vertices, " << land.n_faces() << " faces, colours "
            << (land.has_vertex_colors() ? "set" : "missing") << "\n";
  expect(land.n_vertices() == 65 * 65 && land.has_vertex_colors() && land.has_vertex_normals(), "a coloured terrain");
  OpenMesh::IO::Options colours(OpenMesh::IO::Options::VertexColor);
  if (!OpenMesh::IO::write_mesh(land, out + "/cpp-terrain.off", colours)) throw std::runtime_error("cannot write terrain");
}

/// 6b. Every option of the options structs reaches asperity: set alone on a small base,
/// it changes the result (a misspelt flag would be refused instead).
static void every_option_counts() {
  using T = asperity::TerrainOptions;
  auto terrain_of = [](const T& o) {
    Mesh m = asperity::terrain<Mesh>(o);
    std::vector<float> values;
    for (auto v : m.vertices()) {
      for (int k = 0; k < 3; ++k) values.push_back(m.point(v)[k]);
      for (int k = 0; k < 3; ++k) values.push_back(m.color(v)[k]);
    }
    return values;
  };
  T classic;
  classic.size = 17;
  T dual;
  dual.method = "dual";
  dual.levels = 3;
  T eroded = classic;
  eroded.erode = "thermal";
  eroded.talus = 5.0;
  T tiled = classic;
  tiled.size = 33;
  tiled.tile = std::array<std::uint64_t, 2>{0, 0};
  tiled.tile_size = 17;
  const std::vector<std::pair<T, std::function<void(T&)>>> cases = {
      {classic, [](T& o) { o.method = "smooth"; }},
      {classic, [](T& o) { o.size = 9; }},
      {classic, [](T& o) { o.hurst = 0.3; }},
      {classic, [](T& o) { o.sigma = 2.0; }},
      {classic, [](T& o) { o.seed = 5; }},
      {classic, [](T& o) { o.distribution = "uniform"; }},
      {classic, [](T& o) { o.mean = 0.5; }},
      {classic, [](T& o) { o.variance = 3.0; }},
      {classic, [](T& o) { o.corners = std::array<double, 4>{1, 2, 3, 4}; }},
      {classic, [](T& o) { o.applet = true; }},
      {classic, [](T& o) { o.width = 3.0; }},
      {classic, [](T& o) { o.depth = 3.0; }},
      {classic, [](T& o) { o.max_height = 2.0; }},
      {classic, [](T& o) { o.sea_level = 0.0; }},
      {classic, [](T& o) { o.colors = std::array<std::array<std::uint32_t, 3>, 5>{{{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {10, 11, 12}, {13, 14, 15}}}; }},
      {classic, [](T& o) { o.peak_height = 0.1; }},
      {classic, [](T& o) { o.grid = "triangle"; }},
      {classic, [](T& o) { o.erode = "thermal"; }},
      {eroded, [](T& o) { o.erode_iterations = 3; }},
      {eroded, [](T& o) { o.talus = 60.0; }},
      {tiled, [](T& o) { o.tile = std::array<std::uint64_t, 2>{1, 0}; }},
      {tiled, [](T& o) { o.tile_size = 9; }},
      {dual, [](T& o) { o.x = std::array<double, 3>{2, 0, 0}; }},
      {dual, [](T& o) { o.y = std::array<double, 3>{0, 2, 0}; }},
      {dual, [](T& o) { o.levels = 4; }},
      {dual, [](T& o) { o.deterministic = true; }},
      {dual, [](T& o) { o.cross_product = true; }},
      {dual, [](T& o) { o.no_mean_correction = true; }},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    T changed = cases[i].first;
    cases[i].second(changed);
    expect(terrain_of(changed) != terrain_of(cases[i].first), "terrain option case " + std::to_string(i) + " changes the mesh");
  }
  using N = asperity::NoiseOptions;
  const std::vector<asperity::Vec3> points = {{0.1, 0.2, 0.3}, {1.7, -0.4, 2.2}, {3.1, 0.9, -1.3}, {-2.5, 1.5, 0.7}};
  N fbm;
  fbm.kind = "fbm";
  N multifractal;
  multifractal.kind = "multifractal";
  N gabor;
  gabor.kind = "gabor";
  gabor.f0 = 0.5;
  N phasor = gabor;
  phasor.kind = "phasor";
  const std::vector<std::pair<N, std::function<void(N&)>>> noise_cases = {
      {N(), [](N& o) { o.kind = "turbulence"; }},
      {N(), [](N& o) { o.seed = 3; }},
      {fbm, [](N& o) { o.octaves = 2; }},
      {fbm, [](N& o) { o.lacunarity = 3.0; }},
      {fbm, [](N& o) { o.gain = 0.8; }},
      {multifractal, [](N& o) { o.offset = 0.5; }},
      {gabor, [](N& o) { o.k = 2.0; }},
      {gabor, [](N& o) { o.a = 0.08; }},
      {gabor, [](N& o) { o.f0 = 0.7; }},
      {gabor, [](N& o) { o.omega = 0.3; }},
      {gabor, [](N& o) { o.impulses = 16.0; }},
      {gabor, [](N& o) { o.isotropic = true; }},
      {phasor, [](N& o) { o.profile = "square"; }},
  };
  for (std::size_t i = 0; i < noise_cases.size(); ++i) {
    N changed = noise_cases[i].first;
    noise_cases[i].second(changed);
    expect(asperity::noise(points, changed) != asperity::noise(points, noise_cases[i].first),
           "noise option case " + std::to_string(i) + " changes the values");
  }
  std::cout << "options: " << cases.size() << " terrain and " << noise_cases.size() << " noise options each change the result\n";
}

/// 7. Bad input: typed exceptions with asperity's messages.
static void bad_input(const Mesh& input) {
  auto refused = [](const char* what, auto&& call) {
    try {
      call();
    } catch (const asperity::InputError& e) {
      std::cout << what << " refused: " << e.what() << "\n";
      return;
    }
    throw Failed(std::string(what) + " was accepted");
  };
  refused("bad recipe", [&] {
    Mesh copy = input;
    asperity::detail(copy, "[[step]]\nop = \"shear\"\n");
  });
  refused("terrain size", [] {
    asperity::TerrainOptions o;
    o.size = 100;
    asperity::terrain<Mesh>(o);
  });
  refused("analysis option", [&] {
    asperity::AnalysisOptions o;
    o.corner = 2.0;
    asperity::analyze(static_cast<const Mesh&>(input), o);
  });
  refused("hierarchy option", [&] {
    asperity::HierarchyOptions o;
    o.max_error = -1.0;
    asperity::Hierarchy<Mesh> h(input, o);
  });
  refused("level", [&] {
    asperity::HierarchyOptions o;
    o.levels = 2;
    asperity::Hierarchy<Mesh>(input, o).level(7);
  });
  // #36: a vertex deleted but not yet garbage-collected made "face refers to vertex N but
  // there are N vertices"; the message now says what to do.
  refused("deleted vertex", [&] {
    Mesh copy = input;
    copy.request_vertex_status();
    copy.request_edge_status();
    copy.request_face_status();
    copy.delete_vertex(*copy.vertices_begin());
    asperity::analyze(copy);
  });
}

/// #36: what --repair does, from C++: a mesh with a vertex no face uses (which the other
/// calls refuse) becomes one they take, each vertex naming the input vertex it came from.
static void repair_from_cpp(const Mesh& input) {
  Mesh broken = input;
  broken.add_vertex(Mesh::Point(9, 9, 9));
  const std::string report = asperity::repair(broken);
  std::cout << "repair: " << report << "\n";
  expect(report.find("1 unreferenced vertex dropped") != std::string::npos, "repair drops the unused vertex");
  expect(broken.n_vertices() == input.n_vertices(), "repair keeps every used vertex");
  auto source = OpenMesh::getProperty<OpenMesh::VertexHandle, int>(broken, "asperity:source");
  for (auto v : broken.vertices()) expect(source[v] == v.idx(), "each vertex names the one it came from");
  asperity::simplify(broken, input.n_vertices() / 4);
}

/// #36: C++'s detail reads the recipe's whole [hierarchy] table, as the command line does
/// (it read only target_vertices).
static void recipe_hierarchy_table(const Mesh& input) {
  Mesh two = input;
  auto r = asperity::detail(two, "[hierarchy]\nlevels = 2\n");
  std::cout << "detail with [hierarchy] levels = 2: " << r.levels << " levels\n";
  expect(r.levels == 2, "[hierarchy] levels is applied");
  Mesh bad = input;
  try {
    asperity::detail(bad, "[hierarchy]\nkeep_features = \"most\"\n");
    expect(false, "a bad [hierarchy] keep_features is refused");
  } catch (const asperity::InputError& e) {
    std::cout << "[hierarchy] keep_features refused: " << e.what() << "\n";
  }
  // #38: settings laid over the table one by one, as the command line's flags.
  asperity::HierarchySettings three;
  three.levels = 3;
  Mesh over = input;
  r = asperity::detail(over, "[hierarchy]\nlevels = 2\n", three);
  std::cout << "detail with [hierarchy] levels = 2 under levels = 3: " << r.levels << " levels\n";
  expect(r.levels == 3, "a setting replaces the table's key");
  Mesh unset = input;
  r = asperity::detail(unset, "[hierarchy]\nlevels = 2\n", asperity::HierarchySettings{});
  expect(r.levels == 2, "unset settings leave the table's keys");
  asperity::HierarchySettings wrong;
  wrong.keep_features = "most";
  Mesh refused = input;
  try {
    asperity::detail(refused, "", wrong);
    expect(false, "a bad keep_features setting is refused");
  } catch (const asperity::InputError& e) {
    std::cout << "keep_features setting refused: " << e.what() << "\n";
    expect(std::string(e.what()).find("keep_features") != std::string::npos, "the refusal names the setting");
  }
}

int main(int argc, char** argv) {
  const std::string out = argc > 2 ? argv[2] : ".";
  Mesh input;
  if (argc > 1 && argv[1][0] != '\0') {
    if (!OpenMesh::IO::read_mesh(input, argv[1])) {
      std::cerr << "cannot read " << argv[1] << "\n";
      return 2;
    }
  } else {
    input = sphere();
  }
  std::cout << "asperity " << asperity::version() << " from C++: input " << input.n_vertices() << " vertices, "
            << input.n_faces() << " faces\n";
  try {
    Mesh base = input;
    auto r = asperity::simplify(base, input.n_vertices() / 10);
    std::cout << "simplify: " << r.input_vertices << " => " << r.output_vertices << " vertices, " << r.levels
              << " levels in " << r.seconds << " s\n";
    expect(base.n_vertices() == r.output_vertices && r.output_vertices <= input.n_vertices() / 10, "simplify's budget");
    write(base, out + "/cpp-base.off");

    asperity::HierarchyOptions options;
    options.target_vertices = input.n_vertices() / 20;
    options.keep_features = "none";
    const asperity::Hierarchy<Mesh> hierarchy(input, options);
    levels_and_parametrization(hierarchy, input, out);
    refine_with_an_operator(hierarchy, input, out);
    refine_a_region(hierarchy, input, out);
    textured_levels(input, out);
    analysis_and_noise(input);
    recipe_and_terrain(input, out);
    every_option_counts();
    repair_from_cpp(input);
    recipe_hierarchy_table(input);
    bad_input(input);
  } catch (const Failed& e) {
    std::cerr << "failed: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "asperity failed: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
