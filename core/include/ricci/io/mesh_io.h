// Reading mesh files: OFF, OBJ, PLY (ASCII and binary), STL (ASCII and binary) and GIFTI surfaces,
// each also gzipped (name.gii.gz), by readers of our own (no host application needed). Polygons are
// split into triangles as a fan from their first corner; STL's separate triangle corners are merged
// where their coordinates are equal.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/io/mesh_file.h"
#include "ricci/mesh/compact_mesh.h"

namespace ricci {

//! Reads a mesh file; the format comes from the extension (case-insensitive), and for files
//! without a known extension from the first bytes.
//! \throws IoError naming the file, the line or element, and what was wrong.
MeshFile read_mesh_file(const std::string& path);

//! read_mesh_file, then the compact mesh of its vertices and triangles.
//! \throws IoError, and InvalidMeshError (naming the file) as CompactMesh does.
CompactMesh read_mesh(const std::string& path);

}  // namespace ricci
