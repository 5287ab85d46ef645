// The vcg mesh type of the command line tool and tests, reading OFF/OBJ/PLY/STL through
// vcglib's importers, and the adapter from any vcg::tri mesh to the compact mesh.
#pragma once

#include <string>
#include <vector>

#include <vcg/complex/complex.h>

#include "ricci/compact_mesh.h"

namespace ricci {

namespace vcgmesh {
class Vertex;
class Face;
struct UsedTypes
    : public vcg::UsedTypes<vcg::Use<Vertex>::AsVertexType, vcg::Use<Face>::AsFaceType> {};
class Vertex : public vcg::Vertex<UsedTypes, vcg::vertex::Coord3d, vcg::vertex::Normal3d,
                                  vcg::vertex::BitFlags> {};
class Face : public vcg::Face<UsedTypes, vcg::face::VertexRef, vcg::face::BitFlags> {};
}  // namespace vcgmesh

//! Triangle mesh with double coordinates.
class VcgMesh : public vcg::tri::TriMesh<std::vector<vcgmesh::Vertex>, std::vector<vcgmesh::Face>> {
};

//! Reads OFF, OBJ, PLY or STL (polygons are triangulated; STL's duplicate vertices merged).
//! \throws IoError naming the file and the importer's reason.
void read_mesh(const std::string& path, VcgMesh& mesh);

//! Index arrays of a vcg::tri mesh (deleted elements skipped, vertices in storage order).
//! If vertex_index is given, it receives the compact index of every slot of m.vert (-1 where
//! deleted). \throws InvalidMeshError as CompactMesh does.
template <class MeshT>
CompactMesh compact_mesh_from_vcg(const MeshT& m, std::vector<int>* vertex_index = nullptr) {
  std::vector<int> index(m.vert.size(), -1);
  std::vector<Eigen::Vector3d> positions;
  positions.reserve(m.vn);
  for (size_t i = 0; i < m.vert.size(); ++i) {
    if (m.vert[i].IsD()) continue;
    index[i] = static_cast<int>(positions.size());
    const auto& p = m.vert[i].cP();
    positions.emplace_back(double(p[0]), double(p[1]), double(p[2]));
  }
  std::vector<std::array<int, 3>> faces;
  faces.reserve(m.fn);
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    std::array<int, 3> t;
    for (int c = 0; c < 3; ++c) t[c] = index[f.cV(c) - &m.vert[0]];
    faces.push_back(t);
  }
  if (vertex_index) *vertex_index = index;
  return CompactMesh(std::move(positions), std::move(faces));
}

}  // namespace ricci
