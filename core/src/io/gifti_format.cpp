// GIFTI surfaces (.gii, .surf.gii), the neuroimaging format of FreeSurfer, HCP and nilearn: an
// XML file whose DataArray elements hold the vertices (Intent NIFTI_INTENT_POINTSET, 3 columns)
// and the triangles (NIFTI_INTENT_TRIANGLE, 3 columns), each ASCII, base64 or zlib-compressed
// base64, little or big endian, row- or column-major (GIFTI 1.0, Harwell et al. 2011). Written for
// this project; the XML is read only as far as these elements need, each part of the file looked
// at once, and nothing allocated beyond what the file's own bytes hold.
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "io/text_reader.h"
#include "ricci/mesh/errors.h"

namespace ricci::io {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw IoError("read_mesh: '" + path + "' (GIFTI): " + what);
}

// The value of attribute `name` in an element's start tag, or "".
std::string attribute(std::string_view tag, std::string_view name) {
  size_t at = 0;
  while ((at = tag.find(name, at)) != std::string_view::npos) {
    const bool starts = at > 0 && is_space(tag[at - 1]);
    size_t i = at + name.size();
    while (i < tag.size() && is_space(tag[i])) ++i;
    if (starts && i < tag.size() && tag[i] == '=') {
      ++i;
      while (i < tag.size() && is_space(tag[i])) ++i;
      if (i < tag.size() && (tag[i] == '"' || tag[i] == '\'')) {
        const size_t end = tag.find(tag[i], i + 1);
        if (end != std::string_view::npos) return std::string(tag.substr(i + 1, end - i - 1));
      }
    }
    at += name.size();
  }
  return "";
}

// The text of the first <Data> element in a DataArray's body ("" for <Data/>).
std::string_view data_text(const std::string& path, std::string_view body) {
  size_t at = 0;
  while ((at = body.find("<Data", at)) != std::string_view::npos) {
    const size_t after = at + 5;
    if (after < body.size() &&
        (body[after] == '>' || body[after] == '/' || is_space(body[after]))) {
      const size_t close = body.find('>', after);
      if (close == std::string_view::npos) break;
      if (body[close - 1] == '/') return {};  // <Data/>
      const size_t end = body.find("</Data>", close);
      if (end == std::string_view::npos) break;
      return body.substr(close + 1, end - close - 1);
    }
    at = after;
  }
  fail(path, "a DataArray without its Data");
}

std::string from_base64(const std::string& path, std::string_view text) {
  std::string out;
  out.reserve(text.size() / 4 * 3);
  unsigned buffer = 0;
  int bits = 0;
  for (char c : text) {
    int v;
    if (c >= 'A' && c <= 'Z') {
      v = c - 'A';
    } else if (c >= 'a' && c <= 'z') {
      v = c - 'a' + 26;
    } else if (c >= '0' && c <= '9') {
      v = c - '0' + 52;
    } else if (c == '+') {
      v = 62;
    } else if (c == '/') {
      v = 63;
    } else if (c == '=') {
      break;
    } else if (is_space(c)) {
      continue;
    } else {
      fail(path, std::string("a data array's base64 has the character '") + c + "'");
    }
    buffer = (buffer << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((buffer >> bits) & 0xFF));
    }
  }
  return out;
}

// The width in bytes of a GIFTI data type, or 0 for one not known.
size_t width_of(const std::string& type) {
  if (type == "NIFTI_TYPE_UINT8" || type == "NIFTI_TYPE_INT8") return 1;
  if (type == "NIFTI_TYPE_INT16" || type == "NIFTI_TYPE_UINT16") return 2;
  if (type == "NIFTI_TYPE_FLOAT32" || type == "NIFTI_TYPE_INT32" || type == "NIFTI_TYPE_UINT32")
    return 4;
  if (type == "NIFTI_TYPE_FLOAT64" || type == "NIFTI_TYPE_INT64" || type == "NIFTI_TYPE_UINT64")
    return 8;
  return 0;
}

// One value of `type` from its bytes in the file's byte order.
double value_of(const std::string& type, const char* bytes, size_t width, bool swap) {
  unsigned char b[8];
  std::memcpy(b, bytes, width);
  if (swap) std::reverse(b, b + width);
  const auto as = [&](auto x) {
    std::memcpy(&x, b, sizeof x);
    return static_cast<double>(x);
  };
  if (type == "NIFTI_TYPE_FLOAT32") return as(float{});
  if (type == "NIFTI_TYPE_FLOAT64") return as(double{});
  if (type == "NIFTI_TYPE_INT8") return as(std::int8_t{});
  if (type == "NIFTI_TYPE_UINT8") return as(std::uint8_t{});
  if (type == "NIFTI_TYPE_INT16") return as(std::int16_t{});
  if (type == "NIFTI_TYPE_UINT16") return as(std::uint16_t{});
  if (type == "NIFTI_TYPE_INT32") return as(std::int32_t{});
  if (type == "NIFTI_TYPE_UINT32") return as(std::uint32_t{});
  if (type == "NIFTI_TYPE_INT64") return as(std::int64_t{});
  return as(std::uint64_t{});
}

// One DataArray's values as doubles, in row-major order.
struct DataArray {
  std::vector<double> values;
  size_t rows = 0, columns = 1;
};

DataArray read_array(const std::string& path, std::string_view tag, std::string_view data) {
  DataArray a;
  const std::string type = attribute(tag, "DataType"), encoding = attribute(tag, "Encoding"),
                    order = attribute(tag, "ArrayIndexingOrder"), endian = attribute(tag, "Endian");
  if (encoding == "ExternalFileBinary") {
    fail(path, "its data is in an external file ('" + attribute(tag, "ExternalFileName") +
                   "'), which is not read: write the arrays into the .gii");
  }
  if (encoding != "ASCII" && encoding != "Base64Binary" && encoding != "GZipBase64Binary") {
    fail(path, "a data array encoded as '" + encoding + "'");
  }
  const size_t width = width_of(type);
  if (width == 0) fail(path, "a data array of type '" + type + "'");
  const std::string dimensionality = attribute(tag, "Dimensionality");
  if (dimensionality != "1" && dimensionality != "2") {
    fail(path, "a data array of dimensionality '" + dimensionality + "'");
  }
  const auto dimension = [&](const char* name) {
    const std::string text = attribute(tag, name);
    char* end = nullptr;
    const long long n = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || n < 0 || n > std::numeric_limits<int>::max()) {
      fail(path, std::string("a data array's ") + name + " is '" + text + "'");
    }
    return static_cast<size_t>(n);
  };
  a.rows = dimension("Dim0");
  if (dimensionality == "2") a.columns = dimension("Dim1");
  const size_t count = a.rows * a.columns;  // both below 2^31: no overflow
  if (encoding == "ASCII") {
    // Each value takes a character at least: the count is checked before it is allocated.
    if (count > data.size()) {
      fail(path, "an ASCII data array of " + std::to_string(count) + " values in " +
                     std::to_string(data.size()) + " characters");
    }
    const std::vector<std::string_view> words = tokens(data);
    if (words.size() < count) {
      fail(path, "an ASCII data array has " + std::to_string(words.size()) + " of its " +
                     std::to_string(count) + " values");
    }
    a.values.resize(count);
    for (size_t i = 0; i < count; ++i) {
      if (!parse_number(words[i], a.values[i])) {
        fail(path, "'" + std::string(words[i]) + "' in an ASCII data array is not a number");
      }
    }
  } else {
    std::string bytes = from_base64(path, data);
    if (encoding == "GZipBase64Binary") bytes = inflated(path, bytes, count * width);
    if (bytes.size() != count * width) {
      fail(path, "a data array has " + std::to_string(bytes.size()) + " bytes for its " +
                     std::to_string(count) + " values of " + std::to_string(width));
    }
    a.values.resize(count);
    const bool swap = endian == "BigEndian";
    for (size_t i = 0; i < count; ++i) a.values[i] = value_of(type, &bytes[i * width], width, swap);
  }
  if (order == "ColumnMajorOrder" && a.columns > 1) {
    std::vector<double> rows(count);
    for (size_t r = 0; r < a.rows; ++r) {
      for (size_t c = 0; c < a.columns; ++c) rows[r * a.columns + c] = a.values[c * a.rows + r];
    }
    a.values = std::move(rows);
  }
  return a;
}

}  // namespace

std::string inflated(const std::string& path, std::string_view in, size_t most) {
  if (in.size() > std::numeric_limits<uInt>::max()) fail(path, "compressed data of 4 GB or more");
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) fail(path, "zlib could not start");  // zlib or gzip
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  z.avail_in = static_cast<uInt>(in.size());
  // Grown as the stream yields, never past `most`: a count in the file allocates nothing.
  std::string out;
  Bytef chunk[65536];
  int status = Z_OK;
  while (status == Z_OK) {
    z.next_out = chunk;
    z.avail_out = sizeof chunk;
    status = inflate(&z, Z_NO_FLUSH);
    const size_t got = sizeof chunk - z.avail_out;
    if (out.size() + got > most) {
      status = Z_BUF_ERROR;
      break;
    }
    out.append(reinterpret_cast<const char*>(chunk), got);
  }
  inflateEnd(&z);
  if (status != Z_STREAM_END) {
    fail(path, "compressed data that does not inflate to at most " + std::to_string(most) +
                   " bytes (zlib status " + std::to_string(status) + ")");
  }
  return out;
}

bool is_gifti(std::string_view bytes) {
  return bytes.substr(0, 1024).find("<GIFTI") != std::string_view::npos;
}

MeshFile read_gifti(const std::string& path, std::string_view bytes) {
  MeshFile mesh;
  bool points = false, triangles = false;
  size_t at = 0;
  while (!(points && triangles) && (at = bytes.find("<DataArray", at)) != std::string_view::npos) {
    const size_t tag_end = bytes.find('>', at);
    if (tag_end == std::string_view::npos) fail(path, "a DataArray's tag does not end");
    const std::string_view tag = bytes.substr(at, tag_end - at);
    at = tag_end;
    if (tag.back() == '/') continue;  // <DataArray .../>: no data
    const size_t end = bytes.find("</DataArray>", tag_end);
    if (end == std::string_view::npos) fail(path, "a DataArray does not end");
    at = end;
    const std::string intent = attribute(tag, "Intent");
    const bool is_points = intent == "NIFTI_INTENT_POINTSET" && !points;
    const bool is_triangles = intent == "NIFTI_INTENT_TRIANGLE" && !triangles;
    if (!is_points && !is_triangles) continue;  // per-vertex data, or a surface's second array
    const DataArray a =
        read_array(path, tag, data_text(path, bytes.substr(tag_end + 1, end - tag_end - 1)));
    if (a.columns != 3) fail(path, intent + " with " + std::to_string(a.columns) + " columns");
    if (is_points) {
      points = true;
      for (size_t r = 0; r < a.rows; ++r) {
        mesh.positions.emplace_back(a.values[3 * r], a.values[3 * r + 1], a.values[3 * r + 2]);
      }
    } else {
      triangles = true;
      for (size_t r = 0; r < a.rows; ++r) {
        std::array<int, 3> t{};
        for (size_t k = 0; k < 3; ++k) {
          const double v = a.values[3 * r + k];
          if (!(v >= 0 && v <= std::numeric_limits<int>::max() && v == std::floor(v))) {
            fail(path, "triangle " + std::to_string(r) + " has the index " + std::to_string(v));
          }
          t[k] = static_cast<int>(v);
        }
        mesh.triangles.push_back(t);
      }
    }
  }
  if (!points || !triangles) {
    fail(path, std::string("no ") + (points ? "triangles" : "vertices") +
                   " (a DataArray of Intent " +
                   (points ? "NIFTI_INTENT_TRIANGLE" : "NIFTI_INTENT_POINTSET") +
                   "): a GIFTI file of per-vertex data is no surface");
  }
  return mesh;
}

}  // namespace ricci::io
