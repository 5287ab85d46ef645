#include "picture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>

#include "ricci/mesh/errors.h"

namespace ricci::cli {

namespace {

using Rgb = std::array<std::uint8_t, 3>;

class Image {
 public:
  explicit Image(int size)
      : size_(size), pixels_(static_cast<size_t>(size) * size, Rgb{255, 255, 255}) {}
  int size() const { return size_; }
  void set(int x, int y, const Rgb& c) {
    if (x >= 0 && y >= 0 && x < size_ && y < size_) pixels_[static_cast<size_t>(y) * size_ + x] = c;
  }
  const Rgb& at(int x, int y) const { return pixels_[static_cast<size_t>(y) * size_ + x]; }

 private:
  int size_;
  std::vector<Rgb> pixels_;
};

// Blue (0) - white (0.5) - red (1).
Rgb ramp(double t) {
  t = std::clamp(t, 0.0, 1.0);
  auto mix = [](double a, double b, double s) {
    return static_cast<std::uint8_t>(std::lround(a + (b - a) * s));
  };
  if (t < 0.5) return {mix(40, 245, 2 * t), mix(90, 245, 2 * t), mix(200, 245, 2 * t)};
  return {mix(245, 200, 2 * t - 1), mix(245, 50, 2 * t - 1), mix(245, 40, 2 * t - 1)};
}

void fill_triangle(Image& img, const std::array<Eigen::Vector2d, 3>& p, const Rgb& c) {
  const double x0 = std::min({p[0].x(), p[1].x(), p[2].x()}),
               x1 = std::max({p[0].x(), p[1].x(), p[2].x()});
  const double y0 = std::min({p[0].y(), p[1].y(), p[2].y()}),
               y1 = std::max({p[0].y(), p[1].y(), p[2].y()});
  auto edge = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, double x, double y) {
    return (b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x());
  };
  const double area = edge(p[0], p[1], p[2].x(), p[2].y());
  if (area == 0) return;
  for (int y = static_cast<int>(std::floor(y0)); y <= static_cast<int>(std::ceil(y1)); ++y) {
    for (int x = static_cast<int>(std::floor(x0)); x <= static_cast<int>(std::ceil(x1)); ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double w0 = edge(p[1], p[2], px, py) / area, w1 = edge(p[2], p[0], px, py) / area,
                   w2 = edge(p[0], p[1], px, py) / area;
      if (w0 >= 0 && w1 >= 0 && w2 >= 0) img.set(x, y, c);
    }
  }
}

void draw_line(Image& img, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Rgb& c) {
  const int steps = static_cast<int>(std::ceil((b - a).lpNorm<Eigen::Infinity>())) + 1;
  for (int s = 0; s <= steps; ++s) {
    const Eigen::Vector2d q = a + (b - a) * (static_cast<double>(s) / steps);
    img.set(static_cast<int>(q.x()), static_cast<int>(q.y()), c);
  }
}

// --- PNG: one IDAT with stored (uncompressed) deflate blocks; no compression library needed.
std::uint32_t crc32(const std::uint8_t* data, size_t n, std::uint32_t crc = 0) {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (size_t i = 0; i < n; ++i) crc = table[(crc ^ data[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t x) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(x >> s));
}

void put_chunk(std::ofstream& file, const char* type, const std::vector<std::uint8_t>& data) {
  std::vector<std::uint8_t> chunk;
  put_u32(chunk, static_cast<std::uint32_t>(data.size()));
  chunk.insert(chunk.end(), type, type + 4);
  chunk.insert(chunk.end(), data.begin(), data.end());
  put_u32(chunk, crc32(chunk.data() + 4, chunk.size() - 4));
  file.write(reinterpret_cast<const char*>(chunk.data()),
             static_cast<std::streamsize>(chunk.size()));
}

void write_png(const std::string& path, const Image& img) {
  const int n = img.size();
  std::vector<std::uint8_t> raw;
  raw.reserve(static_cast<size_t>(n) * (3 * n + 1));
  for (int y = 0; y < n; ++y) {
    raw.push_back(0);  // filter: none
    for (int x = 0; x < n; ++x) raw.insert(raw.end(), img.at(x, y).begin(), img.at(x, y).end());
  }
  std::vector<std::uint8_t> z = {0x78, 0x01};
  std::uint32_t a = 1, b = 0;
  for (std::uint8_t byte : raw) {
    a = (a + byte) % 65521;
    b = (b + a) % 65521;
  }
  for (size_t pos = 0; pos < raw.size();) {
    const size_t len = std::min<size_t>(65535, raw.size() - pos);
    z.push_back(pos + len == raw.size() ? 1 : 0);
    z.push_back(static_cast<std::uint8_t>(len & 0xFF));
    z.push_back(static_cast<std::uint8_t>(len >> 8));
    z.push_back(static_cast<std::uint8_t>(~len & 0xFF));
    z.push_back(static_cast<std::uint8_t>((~len >> 8) & 0xFF));
    z.insert(z.end(), raw.begin() + static_cast<long>(pos),
             raw.begin() + static_cast<long>(pos + len));
    pos += len;
  }
  put_u32(z, (b << 16) | a);
  std::vector<std::uint8_t> header;
  put_u32(header, static_cast<std::uint32_t>(n));
  put_u32(header, static_cast<std::uint32_t>(n));
  header.insert(header.end(), {8, 2, 0, 0, 0});  // 8-bit RGB
  std::ofstream file(path, std::ios::binary);
  if (!file) throw IoError("cannot write '" + path + "'");
  const std::uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  file.write(reinterpret_cast<const char*>(signature), 8);
  put_chunk(file, "IHDR", header);
  put_chunk(file, "IDAT", z);
  put_chunk(file, "IEND", {});
  file.close();
  if (!file) throw IoError("writing '" + path + "' failed");
}

}  // namespace

void write_layout_png(const std::string& path, const std::vector<std::array<int, 3>>& faces,
                      const std::vector<Eigen::Vector2d>& uv, const Eigen::VectorXd& value,
                      int size) {
  Image img(size);
  const double margin = 0.04 * size;
  auto to_pixel = [&](const Eigen::Vector2d& t) {
    return Eigen::Vector2d(margin + t.x() * (size - 2 * margin),
                           size - margin - t.y() * (size - 2 * margin));
  };
  // White where the value is 0 (for u: lengths as in the input), blue below, red above.
  double extent = 1e-300;
  for (const auto& t : faces) {
    for (int v : t) extent = std::max(extent, std::abs(value[v]));
  }
  for (const auto& t : faces) {
    std::array<Eigen::Vector2d, 3> p;
    double mean = 0;
    for (int c = 0; c < 3; ++c) {
      p[c] = to_pixel(uv[t[c]]);
      mean += value[t[c]] / 3;
    }
    fill_triangle(img, p, ramp(0.5 + 0.5 * mean / extent));
  }
  if (faces.size() <= 20000) {  // edges of every face (inner ones twice)
    for (const auto& t : faces) {
      for (int c = 0; c < 3; ++c) {
        draw_line(img, to_pixel(uv[t[c]]), to_pixel(uv[t[(c + 1) % 3]]), Rgb{60, 60, 60});
      }
    }
  }
  write_png(path, img);
}

}  // namespace ricci::cli
