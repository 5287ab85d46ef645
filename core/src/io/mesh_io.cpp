#include "ricci/io/mesh_io.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "io/text_reader.h"

namespace ricci {

namespace io {

std::string read_file(const std::string& path) {
  // A directory opens as an empty file, a device may never end: both are refused by what they
  // are. A pipe (a shell's process substitution) ends, and is read.
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (std::filesystem::is_directory(status)) {
    throw IoError("read_mesh: '" + path + "' is a directory, not a mesh file");
  }
  if (std::filesystem::is_character_file(status) || std::filesystem::is_block_file(status) ||
      std::filesystem::is_socket(status)) {
    throw IoError("read_mesh: '" + path + "' is not a regular file (a device or socket)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("read_mesh: cannot open '" + path + "' (missing file or no permission)");
  // Read into a string that grows by append, which throws where memory runs out (a stream's
  // insertion of the file's buffer would only stop there, and leave the file cut short).
  std::string bytes;
  if (std::filesystem::is_regular_file(status)) {
    const std::uintmax_t size = std::filesystem::file_size(path, error);
    if (!error) bytes.reserve(static_cast<size_t>(size));
  }
  std::array<char, 1 << 16> chunk;
  while (in.read(chunk.data(), chunk.size()) || in.gcount() > 0) {
    bytes.append(chunk.data(), static_cast<size_t>(in.gcount()));
  }
  if (in.bad()) throw IoError("read_mesh: reading '" + path + "' failed");
  return bytes;
}

std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  split_tokens(line, out);
  return out;
}

void split_tokens(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

bool LineReader::next(std::vector<std::string_view>& fields) {
  if (pos_ >= text_.size()) return false;
  size_t end = text_.find('\n', pos_);
  if (end == std::string_view::npos) end = text_.size();
  std::string_view line = text_.substr(pos_, end - pos_);
  pos_ = end + 1;
  ++line_;
  const size_t hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  split_tokens(line, fields);
  return true;
}

std::vector<std::string_view> LineReader::next_nonempty(const std::string& what) {
  std::vector<std::string_view> fields;
  if (!next_nonempty(fields)) fail("the file ends before " + what);
  return fields;
}

bool LineReader::next_nonempty(std::vector<std::string_view>& fields) {
  while (next(fields)) {
    if (!fields.empty()) return true;
  }
  return false;
}

void LineReader::fail(const std::string& what) const {
  throw IoError("read_mesh: '" + path_ + "', line " + std::to_string(line_) + ": " + what);
}

bool parse_number(std::string_view token, double& x) {
  // The common case without a copy; strtod's wider syntax (a leading '+', hexadecimal) after.
  const auto [end_fast, error] = std::from_chars(token.data(), token.data() + token.size(), x);
  if (error == std::errc() && end_fast == token.data() + token.size() && !token.empty()) {
    return true;
  }
  const std::string text(token);
  char* end = nullptr;
  errno = 0;
  x = std::strtod(text.c_str(), &end);
  // NaN and infinity are numbers here: the mesh checks name the vertices that have them.
  return !text.empty() && *end == '\0';
}

double LineReader::number(std::string_view token) const {
  double x = 0;
  if (!parse_number(token, x)) fail("'" + std::string(token) + "' is not a number");
  return x;
}

long LineReader::integer(std::string_view token) const {
  long fast = 0;
  const auto [end_fast, error] = std::from_chars(token.data(), token.data() + token.size(), fast);
  if (error == std::errc() && end_fast == token.data() + token.size() && !token.empty()) {
    return fast;
  }
  const std::string text(token);
  char* end = nullptr;
  errno = 0;
  const long x = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE) fail("'" + text + "' is not an integer");
  return x;
}

void add_polygon(MeshFile& mesh, const std::vector<int>& corners) {
  if (corners.size() < 3) {
    ++mesh.skipped_faces;
    return;
  }
  if (corners.size() > 3) ++mesh.polygons;
  for (size_t k = 1; k + 1 < corners.size(); ++k) {
    mesh.triangles.push_back({corners[0], corners[k], corners[k + 1]});
  }
}

}  // namespace io

namespace {

std::string lowercase_extension(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  const size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// The format of a file without a known extension, from its first bytes.
std::string sniff_format(std::string_view bytes) {
  const auto starts = [&](std::string_view s) { return bytes.substr(0, s.size()) == s; };
  if (io::is_ply_magic(bytes.substr(0, 3))) return "ply";
  if (io::is_gifti(bytes)) return "gii";
  if (starts("solid") || starts("SOLID")) return "stl";
  if (bytes.substr(0, bytes.find('\n')).find("OFF") != std::string_view::npos) return "off";
  if (io::is_binary_stl(bytes)) return "stl";
  return "obj";
}

// Text written with a byte order mark, as Windows tools write it: UTF-8's is dropped (before, an
// OBJ lost its first vertex and was refused for a face's index), UTF-16's text is read as the
// ASCII it spells (assimp's test box, big-endian, read as a file of no faces). A binary STL's
// 80-byte header is anything, and is left alone.
std::string_view without_byte_order_mark(const std::string& path, std::string_view bytes,
                                         std::string& decoded) {
  if (io::is_binary_stl(bytes)) return bytes;
  if (bytes.substr(0, 3) == "\xEF\xBB\xBF") return bytes.substr(3);
  const bool big = bytes.substr(0, 2) == "\xFE\xFF", little = bytes.substr(0, 2) == "\xFF\xFE";
  if (!big && !little) return bytes;
  decoded.clear();
  decoded.reserve(bytes.size() / 2);
  for (size_t i = 2; i + 1 < bytes.size(); i += 2) {
    const auto byte = [&](size_t k) {
      return static_cast<unsigned>(static_cast<unsigned char>(bytes[k]));
    };
    const unsigned unit = big ? (byte(i) << 8) | byte(i + 1) : (byte(i + 1) << 8) | byte(i);
    if (unit >= 0x80) {
      throw IoError("read_mesh: '" + path +
                    "' is UTF-16 text with a character outside ASCII (byte " + std::to_string(i) +
                    "); save it as ASCII or UTF-8");
    }
    decoded.push_back(static_cast<char>(unit));
  }
  return decoded;
}

}  // namespace

namespace io {

MeshFile read_mesh_bytes(const std::string& path, std::string_view bytes, std::string format) {
  // A gzipped file (name.gii.gz, as nilearn ships its surfaces; any format): read as the file it
  // holds, named by the extension before .gz, at most 1032 times its size (zlib's largest ratio).
  std::string unzipped;
  const bool known =
      format == "off" || format == "obj" || format == "ply" || format == "stl" || format == "gii";
  if (bytes.substr(0, 2) == "\x1f\x8b" && !known && !is_binary_stl(bytes)) {
    unzipped = inflated(path, bytes, 1032 * bytes.size() + 64);
    bytes = unzipped;
    const std::string inner = path.size() > 3 && lowercase_extension(path) == "gz"
                                  ? lowercase_extension(path.substr(0, path.size() - 3))
                                  : "";
    format = inner == "gz" ? "" : inner;
  }
  std::string decoded;
  bytes = without_byte_order_mark(path, bytes, decoded);
  if (format != "off" && format != "obj" && format != "ply" && format != "stl" && format != "gii") {
    format = sniff_format(bytes);
  }
  MeshFile mesh;
  if (format == "gii") {
    mesh = read_gifti(path, bytes);
  } else if (format == "off") {
    mesh = read_off(path, bytes);
  } else if (format == "obj") {
    mesh = read_obj(path, bytes);
  } else if (format == "ply") {
    mesh = read_ply(path, bytes);
  } else {
    mesh = read_stl(path, bytes);
  }
  mesh.format = format;
  const int n = static_cast<int>(mesh.positions.size());
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int v : mesh.triangles[f]) {
      if (v < 0 || v >= n) {
        throw IoError("read_mesh: '" + path + "': face " + std::to_string(f) +
                      " refers to vertex " + std::to_string(v) + ", but the file has vertices 0.." +
                      std::to_string(n - 1) + "; the file is corrupt, re-export it");
      }
    }
  }
  return mesh;
}

}  // namespace io

MeshFile read_mesh_file(const std::string& path) {
  return io::read_mesh_bytes(path, io::read_file(path), lowercase_extension(path));
}

CompactMesh read_mesh(const std::string& path) {
  MeshFile file = read_mesh_file(path);
  try {
    return CompactMesh(std::move(file.positions), std::move(file.triangles));
  } catch (const InvalidMeshError& e) {
    throw InvalidMeshError(path + ": " + e.what());
  }
}

}  // namespace ricci
