#include "ply_reader.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

namespace ricci::test {

namespace {

struct Property {
  std::string name, type, count_type;  // count_type set for lists
};

double read_scalar(std::istream& in, const std::string& type) {
  auto get = [&](auto value) {
    in.read(reinterpret_cast<char*>(&value), sizeof(value));
    return static_cast<double>(value);
  };
  if (type == "float" || type == "float32") return get(float{});
  if (type == "double" || type == "float64") return get(double{});
  if (type == "uchar" || type == "uint8") return get(std::uint8_t{});
  if (type == "char" || type == "int8") return get(std::int8_t{});
  if (type == "short" || type == "int16") return get(std::int16_t{});
  if (type == "ushort" || type == "uint16") return get(std::uint16_t{});
  if (type == "int" || type == "int32") return get(std::int32_t{});
  if (type == "uint" || type == "uint32") return get(std::uint32_t{});
  ADD_FAILURE() << "unknown PLY type " << type;
  return 0;
}

}  // namespace

PlyData read_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  PlyData ply;
  if (!in) {
    ADD_FAILURE() << "cannot open " << path;
    return ply;
  }
  std::string line, element;
  std::map<std::string, int> count;
  std::map<std::string, std::vector<Property>> properties;
  std::vector<std::string> order;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream s(line);
    std::string word;
    s >> word;
    if (word == "format") {
      s >> ply.format;
    } else if (word == "element") {
      s >> element >> count[element];
      order.push_back(element);
    } else if (word == "property") {
      Property p;
      s >> p.type;
      if (p.type == "list") {
        s >> p.count_type >> p.type;
      }
      s >> p.name;
      properties[element].push_back(p);
    }
  }
  EXPECT_EQ(ply.format, "binary_little_endian") << path;
  for (const auto& p : properties["vertex"]) {
    EXPECT_TRUE(p.count_type.empty()) << "vertex list property " << p.name;
    ply.vertex_properties.push_back(p.name);
    ply.vertex_types[p.name] = p.type;
  }
  for (const auto& e : order) {
    for (int i = 0; i < count[e]; ++i) {
      std::array<int, 3> face{-1, -1, -1};
      for (const auto& p : properties[e]) {
        if (p.count_type.empty()) {
          const double x = read_scalar(in, p.type);
          if (e == "vertex") ply.vertex[p.name].push_back(x);
          if (e == "face") ply.face[p.name].push_back(x);
          continue;
        }
        const int n = static_cast<int>(read_scalar(in, p.count_type));
        std::vector<double> values(n);
        for (double& x : values) x = read_scalar(in, p.type);
        if (e == "face" && p.name == "vertex_indices") {
          EXPECT_EQ(n, 3) << "triangles only";
          for (int c = 0; c < 3 && c < n; ++c) face[c] = static_cast<int>(values[c]);
        } else if (e == "face" && p.name == "texcoord") {
          ply.face_texcoords.push_back(values);
        } else if (e == "face" && p.name == "texcoord_double") {
          ply.face_texcoords_double.push_back(values);
        }
        if (e == "face" && p.name != "vertex_indices") ply.face_lists[p.name].push_back(values);
      }
      if (e == "face") ply.faces.push_back(face);
    }
  }
  EXPECT_TRUE(in.good()) << path << " ended early";
  return ply;
}

}  // namespace ricci::test
