// An independent reader of binary little-endian PLY files, for the end-to-end tests: what
// ricci-flow and meshlabserver write is read back without vcglib.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

namespace ricci::test {

struct PlyData {
  std::string format;
  std::vector<std::string> vertex_properties;  //!< in file order
  std::map<std::string, std::string> vertex_types;
  std::map<std::string, std::vector<double>> vertex;  //!< values by property name
  std::vector<std::array<int, 3>> faces;
  std::vector<std::vector<double>> face_texcoords;         //!< the per-face texcoord list, if any
  std::vector<std::vector<double>> face_texcoords_double;  //!< texcoord_double, if any
  std::map<std::string, std::vector<double>> face;         //!< face scalar properties by name
  //! Face list properties other than vertex_indices, by name: per face its values.
  std::map<std::string, std::vector<std::vector<double>>> face_lists;
  bool has_face(const std::string& name) const {
    return face.count(name) > 0 || face_lists.count(name) > 0;
  }
  bool has_vertex(const std::string& name) const { return vertex.count(name) > 0; }
};

//! Reads vertex scalar properties, triangle faces (vertex_indices) and the faces' other scalar
//! and list properties.
//! Fails the current test (gtest) on anything it does not understand.
PlyData read_ply(const std::string& path);

}  // namespace ricci::test
