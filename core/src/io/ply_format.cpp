// PLY: ASCII, binary little-endian and binary big-endian; every element is read past, the vertex
// element's x, y, z and the face element's index list are kept.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "io/text_reader.h"

namespace ricci::io {

namespace {

struct Property {
  std::string name;
  std::string type;        // scalar type, or the item type of a list
  std::string count_type;  // empty for scalars
};

struct Element {
  std::string name;
  long count = 0;
  std::vector<Property> properties;
};

enum class Encoding { Ascii, LittleEndian, BigEndian };

int type_size(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32") return 4;
  if (type == "float" || type == "float32") return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

// Reads the values of the body, ASCII or binary, one at a time.
class PlyBody {
 public:
  //! `body`: the file's bytes after the header, which start at byte `offset` of the file.
  PlyBody(const std::string& path, std::string_view body, size_t offset, Encoding encoding)
      : path_(path), body_(body), offset_(offset), encoding_(encoding) {}

  double value(const std::string& type) {
    if (encoding_ == Encoding::Ascii) return ascii_value();
    const int size = type_size(type);
    if (pos_ + size > body_.size()) fail("the file ends inside its data");
    unsigned char b[8];
    std::memcpy(b, body_.data() + pos_, size);
    pos_ += size;
    if (encoding_ == Encoding::BigEndian) std::reverse(b, b + size);
    return decode(type, b);
  }

  //! A vertex index: a value of `type` that is an integer within int's range.
  int index(const std::string& type) {
    const double x = value(type);
    if (!(x >= std::numeric_limits<int>::min() && x <= std::numeric_limits<int>::max()) ||
        x != std::floor(x)) {
      char shortest[32];  // the value as written, as far as a double holds it
      const auto end = std::to_chars(shortest, shortest + sizeof shortest, x).ptr;
      fail("a face's vertex index " + std::string(shortest, end) + " is not an integer index");
    }
    return static_cast<int>(x);
  }

  //! The bytes not yet read: each item of an element with properties takes at least one.
  size_t remaining() const { return body_.size() - pos_; }

  //! Names the file and the byte where reading stopped.
  [[noreturn]] void fail(const std::string& what) const {
    throw IoError("read_mesh: '" + path_ + "', byte " + std::to_string(offset_ + pos_) + ": " +
                  what);
  }

 private:
  static double decode(const std::string& type, const unsigned char* b) {
    const auto as = [&](auto x) {
      std::memcpy(&x, b, sizeof x);
      return static_cast<double>(x);
    };
    if (type == "char" || type == "int8") return as(std::int8_t{});
    if (type == "uchar" || type == "uint8") return as(std::uint8_t{});
    if (type == "short" || type == "int16") return as(std::int16_t{});
    if (type == "ushort" || type == "uint16") return as(std::uint16_t{});
    if (type == "int" || type == "int32") return as(std::int32_t{});
    if (type == "uint" || type == "uint32") return as(std::uint32_t{});
    if (type == "float" || type == "float32") return as(float{});
    return as(double{});
  }

  double ascii_value() {
    while (pos_ < body_.size() && is_space(body_[pos_])) ++pos_;
    const size_t start = pos_;
    while (pos_ < body_.size() && !is_space(body_[pos_])) ++pos_;
    if (start == pos_) fail("the file ends inside its data");
    const std::string text(body_.substr(start, pos_ - start));
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (*end != '\0') fail("'" + text + "' in the data is not a number");
    return x;
  }

  const std::string& path_;
  std::string_view body_;
  size_t offset_;
  Encoding encoding_;
  size_t pos_ = 0;
};

struct Header {
  Encoding encoding = Encoding::Ascii;
  std::vector<Element> elements;
};

Header parse_header(const std::string& path, std::string_view text) {
  LineReader header(path, text);
  Header h;
  std::vector<std::string_view> f;
  while (header.next(f)) {
    if (f.empty() || io::is_ply_magic(f[0]) || f[0] == "comment" || f[0] == "obj_info") continue;
    if (f[0] == "format" && f.size() >= 2) {
      if (f[1] == "ascii") {
        h.encoding = Encoding::Ascii;
      } else if (f[1] == "binary_little_endian") {
        h.encoding = Encoding::LittleEndian;
      } else if (f[1] == "binary_big_endian") {
        h.encoding = Encoding::BigEndian;
      } else {
        header.fail("unknown PLY format '" + std::string(f[1]) + "'");
      }
    } else if (f[0] == "element" && f.size() == 3) {
      h.elements.push_back({std::string(f[1]), header.integer(f[2]), {}});
    } else if (f[0] == "property" && !h.elements.empty()) {
      Property p;
      if (f.size() == 5 && f[1] == "list") {
        p = {std::string(f[4]), std::string(f[3]), std::string(f[2])};
      } else if (f.size() == 3) {
        p = {std::string(f[2]), std::string(f[1]), ""};
      } else {
        header.fail("a property line is 'property TYPE NAME' or 'property list COUNT ITEM NAME'");
      }
      if (type_size(p.type) == 0 || (!p.count_type.empty() && type_size(p.count_type) == 0)) {
        header.fail("unknown PLY type in '" + std::string(f.back()) + "'");
      }
      h.elements.back().properties.push_back(p);
    }
    // Any other line (free text some exporters write without 'comment') describes no data.
  }
  return h;
}

}  // namespace

MeshFile read_ply(const std::string& path, std::string_view bytes) {
  const size_t end_header = bytes.find("end_header");
  if (!io::is_ply_magic(bytes.substr(0, 3)) || end_header == std::string_view::npos) {
    throw IoError("read_mesh: '" + path + "' has no PLY header ('ply' ... 'end_header')");
  }
  size_t body_start = bytes.find('\n', end_header);
  body_start = body_start == std::string_view::npos ? bytes.size() : body_start + 1;
  const Header header = parse_header(path, bytes.substr(0, end_header));
  const std::vector<Element>& elements = header.elements;
  const Encoding encoding = header.encoding;
  MeshFile mesh;
  PlyBody body(path, bytes.substr(body_start), body_start, encoding);
  std::vector<int> corners;
  bool has_vertices = false;
  for (const Element& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    int index_list = -1;  // the face element's vertex index list
    for (size_t k = 0; k < e.properties.size() && is_face; ++k) {
      const std::string& n = e.properties[k].name;
      if (!e.properties[k].count_type.empty() &&
          (index_list < 0 || n == "vertex_indices" || n == "vertex_index")) {
        index_list = static_cast<int>(k);
      }
    }
    std::array<int, 3> xyz = {-1, -1, -1};
    for (size_t k = 0; k < e.properties.size() && is_vertex; ++k) {
      const std::string& n = e.properties[k].name;
      if (n == "x" || n == "y" || n == "z") xyz[n[0] - 'x'] = static_cast<int>(k);
    }
    if (is_vertex && (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0)) {
      body.fail("the vertex element has no x, y and z properties");
    }
    has_vertices = has_vertices || is_vertex;
    // Items of an element with no properties hold nothing to read, however many the header
    // declares; every other item takes at least a byte, so the header's count cannot reserve
    // more than the file holds.
    if (e.properties.empty()) continue;
    if (static_cast<unsigned long>(e.count) > body.remaining()) {
      body.fail("the header declares " + std::to_string(e.count) + " elements '" + e.name +
                "', more than the " + std::to_string(body.remaining()) +
                " bytes of data left can hold");
    }
    if (is_vertex) mesh.positions.reserve(static_cast<size_t>(e.count));
    for (long i = 0; i < e.count; ++i) {
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const Property& prop = e.properties[k];
        if (prop.count_type.empty()) {
          const double x = body.value(prop.type);
          for (int c = 0; c < 3; ++c) {
            if (xyz[c] == static_cast<int>(k)) p[c] = x;
          }
          continue;
        }
        const double n = body.value(prop.count_type);
        if (!(n >= 0 && n < 1e6)) body.fail("a list in element '" + e.name + "' has a bad count");
        if (static_cast<int>(k) != index_list) {
          for (int c = 0; c < static_cast<int>(n); ++c) body.value(prop.type);  // texcoord, ...
          continue;
        }
        corners.clear();
        for (int c = 0; c < static_cast<int>(n); ++c) corners.push_back(body.index(prop.type));
        add_polygon(mesh, corners);
      }
      if (is_vertex) mesh.positions.push_back(p);
    }
  }
  if (!has_vertices) body.fail("the file has no vertex element");
  return mesh;
}

}  // namespace ricci::io
