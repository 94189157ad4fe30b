// asperity from C++: a program with its own OpenMesh TriMesh runs the pipeline on it.
//
//   openmesh_pipeline [MESH] [OUT_DIR]
//
// 1. simplify MESH (a sphere made here when none or "" is given) to a tenth of its vertices;
// 2. apply a detail recipe (coarse turbulence, fine Gabor noise) to the original;
// 3. make a terrain;
// 4. show that bad input comes back as a C++ exception with asperity's message.
// Results are written with OpenMesh's own writer. Exit code 0 when everything behaved.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include <asperity/pipeline.hpp>

#include <cmath>
#include <iostream>
#include <string>

using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;

static const char* RECIPE = R"(
seed = 11

[[step]]
op = "variation"
level = 1
noise = { kind = "turbulence", amplitude = 0.04, frequency = 3.0 }

[[step]]
op = "noise"
level = -1
noise = { kind = "gabor", amplitude = 0.004, frequency = 25.0 }
)";

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

int main(int argc, char** argv) {
  const std::string out_dir = argc > 2 ? argv[2] : ".";
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
    if (base.n_vertices() != r.output_vertices || r.output_vertices > input.n_vertices() / 10) return 1;
    write(base, out_dir + "/cpp-base.off");

    Mesh detailed = input;
    r = asperity::detail(detailed, RECIPE, true);
    double moved = 0;
    for (auto v : input.vertices()) moved = std::max(moved, double((detailed.point(v) - input.point(v)).norm()));
    std::cout << "detail: " << r.output_vertices << " vertices over " << r.levels << " levels, largest move " << moved
              << "\n";
    if (detailed.n_vertices() != input.n_vertices() || !(moved > 1e-4) || !std::isfinite(moved)) return 1;
    write(detailed, out_dir + "/cpp-detail.off");

    Mesh land = asperity::terrain<Mesh>("classic", 65, 0.8, 7);
    std::cout << "terrain: " << land.n_vertices() << " vertices, " << land.n_faces() << " faces\n";
    if (land.n_vertices() != 65 * 65) return 1;
    write(land, out_dir + "/cpp-terrain.off");
  } catch (const rust::Error& e) {
    std::cerr << "asperity failed: " << e.what() << "\n";
    return 1;
  }

  // Bad input is an exception carrying asperity's message, never an abort.
  try {
    Mesh copy = input;
    asperity::detail(copy, "[[step]]\nop = \"shear\"\n");
    std::cerr << "a bad recipe was accepted\n";
    return 1;
  } catch (const rust::Error& e) {
    std::cout << "bad recipe refused: " << e.what() << "\n";
  }
  return 0;
}
