#include "result_obj.h"

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <unordered_map>
#include <utility>

#include "ricci/mesh/errors.h"

namespace ricci::cli {

namespace {

// Lines gathered in a buffer and written in blocks; numbers in the shortest form that reads back
// to the same double (std::to_chars), integers 1-based.
class ObjWriter {
 public:
  explicit ObjWriter(std::FILE* f) : f_(f) { buffer_.reserve(kBlock + 256); }
  ~ObjWriter() { flush(); }
  ObjWriter& text(const char* s) {
    buffer_.append(s);
    return *this;
  }
  ObjWriter& number(double x) {
    char digits[32];
    const auto end = std::to_chars(digits, digits + sizeof digits, x).ptr;
    buffer_.push_back(' ');
    buffer_.append(digits, end);
    return *this;
  }
  ObjWriter& index(int i) {
    char digits[16];
    buffer_.append(digits, std::to_chars(digits, digits + sizeof digits, i + 1).ptr);
    return *this;
  }
  void end_line() {
    buffer_.push_back('\n');
    if (buffer_.size() >= kBlock) flush();
  }
  void flush() {
    if (!buffer_.empty()) std::fwrite(buffer_.data(), 1, buffer_.size(), f_);
    buffer_.clear();
  }

 private:
  static constexpr size_t kBlock = 1 << 16;
  std::FILE* f_;
  std::string buffer_;
};

// A corner's key: its vertex and its texture coordinates' bits.
struct CornerKey {
  int vertex;
  std::uint64_t x, y;
  bool operator==(const CornerKey& o) const { return vertex == o.vertex && x == o.x && y == o.y; }
};
struct CornerHash {
  size_t operator()(const CornerKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.vertex) * 0x9E3779B97F4A7C15ull;
    h ^= k.x + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h ^= k.y + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    return static_cast<size_t>(h);
  }
};

std::uint64_t bits_of(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

}  // namespace

void write_result_obj(const std::string& path, const MeshUniformization& run) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> out(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!out) throw IoError("cannot write '" + path + "' (missing folder or no permission)");
  std::FILE* f = out.get();
  {
    ObjWriter w(f);
    w.text("# ricci-flow result: unified discrete surface Ricci flow").end_line();
    for (const Eigen::Vector3d& p : run.positions) {
      w.text("v").number(p.x()).number(p.y()).number(p.z()).end_line();
    }
    const auto& faces = run.faces;
    const auto face = [&](const std::array<int, 3>& t, const std::array<int, 3>* texture) {
      w.text("f");
      for (int c = 0; c < 3; ++c) {
        w.text(" ").index(t[c]);
        if (texture) w.text("/").index((*texture)[c]);
      }
      w.end_line();
    };
    if (!run.texture.vertex.empty()) {
      for (const Eigen::Vector2d& t : run.texture.vertex) {
        w.text("vt").number(t.x()).number(t.y()).end_line();
      }
      for (const auto& t : faces) face(t, &t);
    } else if (!run.texture.wedge.empty()) {
      // One texture vertex per vertex and distinct position (to the bit), numbered in the order
      // first met: corners of a wedge share it.
      std::unordered_map<CornerKey, int, CornerHash> index;
      index.reserve(faces.size() * 2);
      std::vector<std::array<int, 3>> corner(faces.size());
      for (size_t k = 0; k < faces.size(); ++k) {
        for (int c = 0; c < 3; ++c) {
          const Eigen::Vector2d& t = run.texture.wedge[k][c];
          const CornerKey key{faces[k][c], bits_of(t.x() + 0.0), bits_of(t.y() + 0.0)};  // -0 as 0
          const auto [at, added] = index.emplace(key, static_cast<int>(index.size()));
          if (added) w.text("vt").number(t.x()).number(t.y()).end_line();
          corner[k][c] = at->second;
        }
      }
      for (size_t k = 0; k < faces.size(); ++k) face(faces[k], &corner[k]);
    } else {
      for (const auto& t : faces) face(t, nullptr);
    }
  }
  if (std::ferror(f)) throw IoError("cannot write '" + path + "' (disk full?)");
}

}  // namespace ricci::cli
