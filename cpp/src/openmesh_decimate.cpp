// OpenMesh's quadric decimater as a reference (see reference_decimators.hpp).
#include <cmath>
#include <sstream>

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include "asperity/reference_decimators.hpp"

namespace asperity {

DecimatedArrays openmesh_decimate(const TriangleArrays& in, std::size_t target_vertices) {
  HalfEdgeMesh store;
  const auto rejected = store.add_geometry(in.xyz, in.n_coords, in.tris, in.n_indices);
  if (!rejected.empty()) {
    std::ostringstream msg;
    msg << "OpenMesh decimater: " << rejected.size() << " face(s) are non-manifold, e.g. face " << rejected[0];
    throw NativeError(msg.str());
  }
  TriMesh& mesh = store.openmesh();
  using Decimater = OpenMesh::Decimater::DecimaterT<TriMesh>;
  using Quadric = OpenMesh::Decimater::ModQuadricT<TriMesh>::Handle;
  Decimater decimater(mesh);
  Quadric quadric;
  decimater.add(quadric);
  decimater.module(quadric).unset_max_err();
  if (!decimater.initialize()) throw NativeError("OpenMesh decimater: initialisation failed");
  decimater.decimate_to(target_vertices);
  const ExportedArrays e = store.export_arrays();
  return DecimatedArrays{e.positions, e.triangles};
}

}  // namespace asperity
