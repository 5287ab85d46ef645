// A mesh file as read: its positions and triangles in file order, and what reading changed.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ricci {

//! What a mesh file holds, as read: nothing is checked or repaired here.
struct MeshFile {
  std::string format;                         //!< "off", "obj", "ply", "stl", "gii"
  std::vector<Eigen::Vector3d> positions;     //!< in file order
  std::vector<std::array<int, 3>> triangles;  //!< polygons already split, in file order
  int polygons = 0;                           //!< faces with more than three corners, split
  int merged_corners = 0;                     //!< STL: corners merged into an earlier vertex
  int skipped_faces = 0;                      //!< faces with fewer than three corners
};

}  // namespace ricci
