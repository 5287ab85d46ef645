// The adapter from vcglib's meshes (MeshLab's CMeshO, or any vcg::tri::TriMesh) to the core's
// index arrays (repair_mesh, then components of CompactMesh). A template over the mesh type: it
// uses vcglib's member names only, so the core does not depend on vcglib; whoever includes this has
// vcglib.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

namespace ricci {

//! The live vertices' positions (in storage order) and the live faces on their indices. If
//! vertex_index is given, it receives the index of every slot of m.vert (-1 where deleted).
template <class MeshT>
void mesh_arrays_from_vcg(const MeshT& m, std::vector<Eigen::Vector3d>& positions,
                          std::vector<std::array<int, 3>>& faces,
                          std::vector<int>* vertex_index = nullptr) {
  std::vector<int> index(m.vert.size(), -1);
  positions.clear();
  positions.reserve(m.vn);
  for (size_t i = 0; i < m.vert.size(); ++i) {
    if (m.vert[i].IsD()) continue;
    index[i] = static_cast<int>(positions.size());
    const auto& p = m.vert[i].cP();
    positions.emplace_back(double(p[0]), double(p[1]), double(p[2]));
  }
  faces.clear();
  faces.reserve(m.fn);
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    std::array<int, 3> t;
    for (int c = 0; c < 3; ++c) t[c] = index[f.cV(c) - &m.vert[0]];
    faces.push_back(t);
  }
  if (vertex_index) *vertex_index = std::move(index);
}

}  // namespace ricci
