// asperity — the reference decimators `asperity compare` measures itself against:
// OpenMesh's DecimaterT with ModQuadricT, and CGAL's edge_collapse with the Garland–Heckbert
// plane policies. Inputs are triangle arrays; outputs are compacted triangle arrays.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "asperity/cgal_ops.hpp"

namespace asperity {

/// A decimated mesh.
struct DecimatedArrays {
  std::vector<double> positions;        ///< xyz per vertex
  std::vector<std::uint32_t> triangles; ///< three vertex indices per face
};

/// OpenMesh `Decimater::DecimaterT` + `ModQuadricT`, down to `target_vertices`.
DecimatedArrays openmesh_decimate(const TriangleArrays& mesh, std::size_t target_vertices);

/// CGAL `Surface_mesh_simplification::edge_collapse` with `GarlandHeckbert_plane_policies`
/// (cost and placement), stopping when the edge count implied by `target_vertices` on a
/// surface of the input's Euler characteristic is reached.
DecimatedArrays cgal_decimate(const TriangleArrays& mesh, std::size_t target_vertices);

}  // namespace asperity
