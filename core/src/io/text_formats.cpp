// OFF, OBJ and STL.
#include <cctype>
#include <cstdint>
#include <cstring>
#include <string>
#include <unordered_map>
#include <utility>

#include "io/text_reader.h"

namespace ricci::io {

namespace {

// "OFF" with optional prefixes for per-vertex data (COFF, NOFF, STOFF, ...): their values follow
// the coordinates on each vertex line and are ignored.
bool is_off_keyword(std::string_view t) {
  return t.size() >= 3 && t.substr(t.size() - 3) == "OFF" &&
         t.find('4') == std::string_view::npos && t.find('n') == std::string_view::npos;
}

// An OBJ face corner "v", "v/vt", "v//vn" or "v/vt/vn": the vertex index, 1-based, or negative
// counting back from the last vertex read.
int obj_vertex(const LineReader& reader, std::string_view corner, int num_vertices) {
  const long i = reader.integer(corner.substr(0, corner.find('/')));
  if (i == 0)
    reader.fail("face corner '" + std::string(corner) + "': OBJ vertex indices start at 1");
  return reader.vertex_index(i > 0 ? i - 1 : num_vertices + i, i, [&] {
    return std::pair("face corner '" + std::string(corner) + "'",
                     std::to_string(num_vertices) + " vertices read so far");
  });
}

// One STL vertex, by its exact coordinates (-0 and +0 alike), compared bit by bit: NaN corners of
// one bit pattern are one key too (by value NaN != NaN made every NaN corner a new key of one
// hash, and the merge quadratic: 100k such triangles took 99 s).
struct CornerKey {
  std::array<double, 3> x;
  bool operator==(const CornerKey& o) const {
    return std::memcmp(x.data(), o.x.data(), sizeof x) == 0;
  }
};
struct CornerHash {
  size_t operator()(const CornerKey& k) const {
    size_t h = 0;
    for (double c : k.x) {
      std::uint64_t bits;
      std::memcpy(&bits, &c, sizeof bits);
      h ^= std::hash<std::uint64_t>()(bits) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    }
    return h;
  }
};

class CornerMerger {
 public:
  explicit CornerMerger(MeshFile& mesh) : mesh_(mesh) {}
  int add(double x, double y, double z) {
    const CornerKey key{{x + 0.0, y + 0.0, z + 0.0}};
    const auto [it, inserted] = index_.emplace(key, static_cast<int>(mesh_.positions.size()));
    if (inserted) {
      mesh_.positions.emplace_back(x, y, z);
    } else {
      ++mesh_.merged_corners;
    }
    return it->second;
  }

 private:
  MeshFile& mesh_;
  std::unordered_map<CornerKey, int, CornerHash> index_;
};

float little_endian_float(const char* p) {
  std::uint32_t bits = 0;
  for (int k = 3; k >= 0; --k) bits = (bits << 8) | static_cast<unsigned char>(p[k]);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

std::uint32_t little_endian_uint32(const char* p) {
  std::uint32_t x = 0;
  for (int k = 3; k >= 0; --k) x = (x << 8) | static_cast<unsigned char>(p[k]);
  return x;
}

std::string lowercase(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

bool is_ply_magic(std::string_view word) {
  return lowercase(word) == "ply";
}

bool is_binary_stl(std::string_view bytes) {
  return bytes.size() >= 84 &&
         84 + 50 * static_cast<std::uint64_t>(little_endian_uint32(bytes.data() + 80)) ==
             bytes.size();
}

MeshFile read_off(const std::string& path, std::string_view text) {
  LineReader reader(path, text);
  MeshFile mesh;
  std::vector<std::string_view> header = reader.next_nonempty("the OFF keyword");
  if (!is_off_keyword(header[0])) {
    reader.fail("'" + std::string(header[0]) + "' is not an OFF keyword (OFF, COFF, NOFF, ...)");
  }
  if (header.size() > 1 && header[1] == "BINARY") reader.fail("binary OFF files are not read");
  header.erase(header.begin());
  if (header.empty()) header = reader.next_nonempty("the vertex and face counts");
  const long nv = reader.integer(header[0]);
  const long nf = header.size() > 1 ? reader.integer(header[1]) : -1;
  if (nv < 0 || nf < 0) reader.fail("expected the vertex and face counts");
  // The header's counts are not trusted for memory: a vertex line takes at least 6 bytes
  // ("0 0 0\n"), a face line at least 2.
  if (static_cast<unsigned long>(nv) > text.size() / 6 ||
      static_cast<unsigned long>(nf) > text.size() / 2) {
    reader.fail("the header declares " + std::to_string(nv) + " vertices and " +
                std::to_string(nf) + " faces, more than the file's " + std::to_string(text.size()) +
                " bytes can hold");
  }
  mesh.positions.reserve(static_cast<size_t>(nv));
  std::vector<std::string_view> f;
  for (long v = 0; v < nv; ++v) {
    if (!reader.next_nonempty(f)) {
      reader.fail("the file ends before vertex " + std::to_string(v) + " of " + std::to_string(nv));
    }
    if (f.size() < 3) reader.fail("a vertex needs three coordinates");
    mesh.positions.emplace_back(reader.number(f[0]), reader.number(f[1]), reader.number(f[2]));
  }
  std::vector<int> corners;
  mesh.triangles.reserve(static_cast<size_t>(nf));
  for (long k = 0; k < nf; ++k) {
    if (!reader.next_nonempty(f)) {
      reader.fail("the file ends before face " + std::to_string(k) + " of " + std::to_string(nf));
    }
    const long n = reader.integer(f[0]);
    if (n < 0 || static_cast<size_t>(n) + 1 > f.size()) {
      reader.fail("the face lists " + std::to_string(f.size() - 1) + " numbers after its count " +
                  std::to_string(n));
    }
    corners.clear();
    for (long c = 1; c <= n; ++c) {
      const long v = reader.integer(f[c]);
      corners.push_back(reader.vertex_index(v, v, [&] {
        return std::pair("face " + std::to_string(k), std::to_string(nv) + " vertices");
      }));
    }
    add_polygon(mesh, corners);
  }
  return mesh;
}

MeshFile read_obj(const std::string& path, std::string_view text) {
  LineReader reader(path, text);
  MeshFile mesh;
  std::vector<std::string_view> f;
  std::vector<int> corners;
  while (reader.next(f)) {
    if (f.empty()) continue;
    if (f[0] == "v") {
      if (f.size() < 4) reader.fail("a vertex needs three coordinates");
      mesh.positions.emplace_back(reader.number(f[1]), reader.number(f[2]), reader.number(f[3]));
    } else if (f[0] == "f" || f[0] == "fo") {
      corners.clear();
      const int n = static_cast<int>(mesh.positions.size());
      for (size_t c = 1; c < f.size(); ++c) corners.push_back(obj_vertex(reader, f[c], n));
      add_polygon(mesh, corners);
    }
    // vt, vn, g, o, s, usemtl, mtllib, l, p: nothing the surface needs.
  }
  return mesh;
}

MeshFile read_stl(const std::string& path, std::string_view bytes) {
  MeshFile mesh;
  CornerMerger merger(mesh);
  if (is_binary_stl(bytes)) {
    const std::uint32_t n = little_endian_uint32(bytes.data() + 80);
    for (std::uint32_t t = 0; t < n; ++t) {
      const char* facet = bytes.data() + 84 + 50 * static_cast<size_t>(t) + 12;  // after normal
      std::array<int, 3> corner;
      for (int c = 0; c < 3; ++c) {
        const char* p = facet + 12 * c;
        corner[c] = merger.add(little_endian_float(p), little_endian_float(p + 4),
                               little_endian_float(p + 8));
      }
      mesh.triangles.push_back(corner);
    }
    return mesh;
  }
  LineReader reader(path, bytes);
  std::vector<std::string_view> f;
  std::vector<int> corners;
  bool solid = false;
  while (reader.next(f)) {
    if (f.empty()) continue;
    const std::string keyword = lowercase(f[0]);  // some exporters write SOLID, VERTEX, ...
    if (keyword == "solid") solid = true;
    if (keyword == "vertex") {
      if (f.size() < 4) reader.fail("a vertex needs three coordinates");
      corners.push_back(merger.add(reader.number(f[1]), reader.number(f[2]), reader.number(f[3])));
    } else if (keyword == "endloop" || keyword == "endfacet") {
      if (!corners.empty()) add_polygon(mesh, corners);
      corners.clear();
    }
  }
  if (!solid) {
    throw IoError("read_mesh: '" + path +
                  "' is neither ASCII STL (no 'solid') nor binary STL (its size is not 84 bytes "
                  "plus 50 per triangle)");
  }
  if (mesh.triangles.empty() && bytes.size() >= 84 && bytes.find('\0') != std::string_view::npos) {
    // A binary STL whose 80-byte header starts with "solid", as some exporters write it.
    const std::uint64_t count = little_endian_uint32(bytes.data() + 80);
    throw IoError("read_mesh: '" + path +
                  "' starts like ASCII STL ('solid') but has no facets; read as binary STL, its "
                  "count of " +
                  std::to_string(count) + " triangles needs " + std::to_string(84 + 50 * count) +
                  " bytes, and the file has " + std::to_string(bytes.size()));
  }
  return mesh;
}

}  // namespace ricci::io
