// GIFTI surfaces (.gii, .surf.gii), the neuroimaging format of FreeSurfer, HCP and nilearn: an
// XML file whose DataArray elements hold the vertices (Intent NIFTI_INTENT_POINTSET, 3 columns)
// and the triangles (NIFTI_INTENT_TRIANGLE, 3 columns), each ASCII, base64 or zlib-compressed
// base64, little or big endian, row- or column-major (GIFTI 1.0, Harwell et al. 2011). Written for
// this project; the XML is read only as far as these elements need.
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
    const bool starts = at > 0 && std::isspace(static_cast<unsigned char>(tag[at - 1]));
    size_t i = at + name.size();
    while (i < tag.size() && std::isspace(static_cast<unsigned char>(tag[i]))) ++i;
    if (starts && i < tag.size() && tag[i] == '=') {
      ++i;
      while (i < tag.size() && std::isspace(static_cast<unsigned char>(tag[i]))) ++i;
      if (i < tag.size() && (tag[i] == '"' || tag[i] == '\'')) {
        const size_t end = tag.find(tag[i], i + 1);
        if (end != std::string_view::npos) return std::string(tag.substr(i + 1, end - i - 1));
      }
    }
    at += name.size();
  }
  return "";
}

std::vector<unsigned char> from_base64(const std::string& path, std::string_view text) {
  std::vector<unsigned char> out;
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
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      continue;
    } else {
      fail(path, std::string("a data array's base64 has the character '") + c + "'");
    }
    buffer = (buffer << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((buffer >> bits) & 0xFF));
    }
  }
  return out;
}

std::vector<unsigned char> inflated(const std::string& path, const std::vector<unsigned char>& in,
                                    size_t expected) {
  if (in.size() > std::numeric_limits<uInt>::max() || expected > std::numeric_limits<uInt>::max()) {
    fail(path, "a compressed data array of 4 GB or more");
  }
  std::vector<unsigned char> out(expected);
  z_stream z{};
  if (inflateInit(&z) != Z_OK) fail(path, "zlib could not start");
  z.next_in = const_cast<unsigned char*>(in.data());
  z.avail_in = static_cast<uInt>(in.size());
  z.next_out = out.data();
  z.avail_out = static_cast<uInt>(out.size());
  const int status = inflate(&z, Z_FINISH);
  const size_t got = out.size() - z.avail_out;
  inflateEnd(&z);
  if (status != Z_STREAM_END || got != expected) {
    fail(path, "a data array's compressed data does not inflate to its " +
                   std::to_string(expected) + " bytes (zlib status " + std::to_string(status) +
                   ", " + std::to_string(got) + " bytes)");
  }
  return out;
}

// One DataArray's values as doubles, in row-major order.
struct DataArray {
  std::string intent;
  std::vector<double> values;
  size_t rows = 0, columns = 1;
};

DataArray read_array(const std::string& path, std::string_view tag, std::string_view data) {
  DataArray a;
  a.intent = attribute(tag, "Intent");
  const std::string type = attribute(tag, "DataType"), encoding = attribute(tag, "Encoding"),
                    order = attribute(tag, "ArrayIndexingOrder"), endian = attribute(tag, "Endian");
  const std::string dimensionality = attribute(tag, "Dimensionality");
  if (dimensionality != "1" && dimensionality != "2") {
    fail(path, "a data array of dimensionality '" + dimensionality + "'");
  }
  // Each dimension a count the data could hold (each value takes a character at least, or
  // compressed, a 1032th of a byte: zlib's largest ratio), checked before anything is allocated.
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
  const size_t count = a.rows * a.columns;
  if (a.columns > 0 && count / a.columns != a.rows) fail(path, "a data array's size overflows");
  size_t width = 0;
  if (type == "NIFTI_TYPE_FLOAT32" || type == "NIFTI_TYPE_INT32" || type == "NIFTI_TYPE_UINT32") {
    width = 4;
  } else if (type == "NIFTI_TYPE_FLOAT64") {
    width = 8;
  } else if (type == "NIFTI_TYPE_UINT8") {
    width = 1;
  } else {
    fail(path, "a data array of type '" + type + "'");
  }
  const size_t most = encoding == "GZipBase64Binary" ? 1032 * data.size() + 64 : data.size();
  if (count > most || count * width / width != count ||
      (encoding != "ASCII" && count * width > most)) {
    fail(path, "a data array of " + std::to_string(count) + " values in " +
                   std::to_string(data.size()) + " characters of data");
  }
  a.values.resize(count);
  if (encoding == "ASCII") {
    std::string text(data);
    const char* p = text.c_str();
    for (size_t i = 0; i < count; ++i) {
      char* end = nullptr;
      a.values[i] = std::strtod(p, &end);
      if (end == p)
        fail(path, "an ASCII data array has fewer than its " + std::to_string(count) + " values");
      p = end;
    }
  } else if (encoding == "Base64Binary" || encoding == "GZipBase64Binary") {
    std::vector<unsigned char> bytes = from_base64(path, data);
    if (encoding == "GZipBase64Binary") bytes = inflated(path, bytes, count * width);
    if (bytes.size() != count * width) {
      fail(path, "a data array has " + std::to_string(bytes.size()) + " bytes for its " +
                     std::to_string(count) + " values");
    }
    const bool swap = endian == "BigEndian";
    for (size_t i = 0; i < count; ++i) {
      unsigned char b[8];
      std::memcpy(b, bytes.data() + i * width, width);
      if (swap) std::reverse(b, b + width);
      if (type == "NIFTI_TYPE_FLOAT32") {
        float f;
        std::memcpy(&f, b, 4);
        a.values[i] = f;
      } else if (type == "NIFTI_TYPE_FLOAT64") {
        std::memcpy(&a.values[i], b, 8);
      } else if (type == "NIFTI_TYPE_INT32") {
        std::int32_t k;
        std::memcpy(&k, b, 4);
        a.values[i] = k;
      } else if (type == "NIFTI_TYPE_UINT32") {
        std::uint32_t k;
        std::memcpy(&k, b, 4);
        a.values[i] = k;
      } else {
        a.values[i] = b[0];
      }
    }
  } else {
    fail(path, "a data array encoded as '" + encoding + "' (external files are not read)");
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

bool is_gifti(std::string_view bytes) {
  return bytes.substr(0, 1024).find("<GIFTI") != std::string_view::npos;
}

MeshFile read_gifti(const std::string& path, std::string_view bytes) {
  MeshFile mesh;
  bool points = false, triangles = false;
  size_t at = 0;
  while ((at = bytes.find("<DataArray", at)) != std::string_view::npos) {
    const size_t tag_end = bytes.find('>', at);
    if (tag_end == std::string_view::npos) fail(path, "a DataArray's tag does not end");
    const std::string_view tag = bytes.substr(at, tag_end - at);
    const size_t open = bytes.find("<Data>", tag_end), close = bytes.find("</Data>", tag_end);
    const size_t array_end = bytes.find("</DataArray>", tag_end);
    if (open == std::string_view::npos || close == std::string_view::npos || close < open ||
        (array_end != std::string_view::npos && open > array_end)) {
      fail(path, "a DataArray without its Data");
    }
    at = close;
    const std::string intent = attribute(tag, "Intent");
    if (intent != "NIFTI_INTENT_POINTSET" && intent != "NIFTI_INTENT_TRIANGLE") continue;
    const DataArray a = read_array(path, tag, bytes.substr(open + 6, close - open - 6));
    if (a.columns != 3) fail(path, intent + " with " + std::to_string(a.columns) + " columns");
    if (intent == "NIFTI_INTENT_POINTSET" && !points) {
      points = true;
      for (size_t r = 0; r < a.rows; ++r) {
        mesh.positions.emplace_back(a.values[3 * r], a.values[3 * r + 1], a.values[3 * r + 2]);
      }
    } else if (intent == "NIFTI_INTENT_TRIANGLE" && !triangles) {
      triangles = true;
      for (size_t r = 0; r < a.rows; ++r) {
        std::array<int, 3> t{};
        for (int k = 0; k < 3; ++k) {
          const double v = a.values[3 * r + static_cast<size_t>(k)];
          if (!(v >= 0 && v <= std::numeric_limits<int>::max() && v == std::floor(v))) {
            fail(path, "triangle " + std::to_string(r) + " has the index " + std::to_string(v));
          }
          t[static_cast<size_t>(k)] = static_cast<int>(v);
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
