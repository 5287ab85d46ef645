// Reading mesh files: OFF, OBJ, PLY (ASCII and binary) and STL (ASCII and binary), by readers of
// our own (no host application needed). Polygons are split into triangles as a fan from their
// first corner; STL's separate triangle corners are merged where their coordinates are equal.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/compact_mesh.h"

namespace ricci {

//! What a mesh file holds, as read: nothing is checked or repaired here.
struct MeshFile {
  std::string format;                         //!< "off", "obj", "ply", "stl"
  std::vector<Eigen::Vector3d> positions;     //!< in file order
  std::vector<std::array<int, 3>> triangles;  //!< polygons already split, in file order
  int polygons = 0;                           //!< faces with more than three corners, split
  int merged_corners = 0;                     //!< STL: corners merged into an earlier vertex
  int skipped_faces = 0;                      //!< faces with fewer than three corners
};

//! Reads a mesh file; the format comes from the extension (case-insensitive), and for files
//! without a known extension from the first bytes.
//! \throws IoError naming the file, the line or element, and what was wrong.
MeshFile read_mesh_file(const std::string& path);

//! read_mesh_file, then the compact mesh of its vertices and triangles.
//! \throws IoError, and InvalidMeshError (naming the file) as CompactMesh does.
CompactMesh read_mesh(const std::string& path);

}  // namespace ricci
