// What the mesh readers share: the file's bytes, lines without comments, numbers that name the
// line they came from, and how polygons become triangles (not installed API).
#pragma once

#include <array>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "ricci/io/mesh_file.h"
#include "ricci/mesh/errors.h"

namespace ricci::io {

//! The whole file. \throws IoError when it cannot be opened or read.
std::string read_file(const std::string& path);

//! std::isspace in the "C" locale, without a call per character.
inline bool is_space(char c) {
  return c == ' ' || (c >= '\t' && c <= '\r');
}

//! A number as every reader takes one: std::from_chars, else strtod's wider syntax (a leading '+',
//! hexadecimal); NaN and infinity included. False where `token` is none.
bool parse_number(std::string_view token, double& x);

//! Splits a line into whitespace-separated tokens.
std::vector<std::string_view> tokens(std::string_view line);
//! The same into `out`, reusing its storage.
void split_tokens(std::string_view line, std::vector<std::string_view>& out);

//! Walks a text file line by line; `#` starts a comment.
class LineReader {
 public:
  LineReader(const std::string& path, std::string_view text) : path_(path), text_(text) {}
  //! The next line with its comment removed and its tokens; false at the end of the file.
  bool next(std::vector<std::string_view>& fields);
  //! The next line that has tokens. \throws IoError at the end of the file, naming `what`.
  std::vector<std::string_view> next_nonempty(const std::string& what);
  //! The next line that has tokens, into `fields`; false at the end of the file.
  bool next_nonempty(std::vector<std::string_view>& fields);
  int line_number() const { return line_; }
  [[noreturn]] void fail(const std::string& what) const;
  double number(std::string_view token) const;
  long integer(std::string_view token) const;
  //! A vertex index `value` (0-based) as int. \throws IoError, saying "WHERE: vertex index
  //! `as_written` is out of range (CONTEXT)" with {WHERE, CONTEXT} = describe(), for one below 0
  //! or past int's range (describe runs only then: this is every face corner's check).
  template <class Describe>
  int vertex_index(long value, long as_written, const Describe& describe) const {
    if (value < 0 || value > std::numeric_limits<int>::max()) {
      const auto [where, context] = describe();
      fail(where + ": vertex index " + std::to_string(as_written) + " is out of range (" + context +
           ")");
    }
    return static_cast<int>(value);
  }

 private:
  const std::string& path_;
  std::string_view text_;
  size_t pos_ = 0;
  int line_ = 0;
};

//! Adds a polygon (vertex indices in order) as a fan of triangles from its first corner.
void add_polygon(MeshFile& mesh, const std::vector<int>& corners);

//! True when the bytes have the size of a binary STL file with the triangle count they state.
bool is_binary_stl(std::string_view bytes);

//! True for a PLY file's first word, "ply", in any case: the format says "ply", and COMPAS
//! (a Python framework for architecture) writes "PLY".
bool is_ply_magic(std::string_view word);

MeshFile read_off(const std::string& path, std::string_view text);
MeshFile read_obj(const std::string& path, std::string_view text);
MeshFile read_stl(const std::string& path, std::string_view bytes);
MeshFile read_ply(const std::string& path, std::string_view bytes);
//! GIFTI (gifti_format.cpp): the first vertex and triangle arrays.
bool is_gifti(std::string_view bytes);
MeshFile read_gifti(const std::string& path, std::string_view bytes);
//! A zlib or gzip stream inflated, grown as it yields and never past `most` bytes.
//! \throws IoError where it does not inflate whole within that.
std::string inflated(const std::string& path, std::string_view in, size_t most);

//! The mesh a file's bytes hold, read as `format` ("off", "obj", "ply", "stl", "gii"; any other: by
//! the first bytes; gzipped bytes read with no such format are inflated first, the format then by
//! the extension before `path`'s .gz) and its face indices checked against its vertices:
//! read_mesh_file's reading, and
//! what the fuzz targets (tests/fuzz/) run.
//! \throws IoError naming `path` and what is wrong.
MeshFile read_mesh_bytes(const std::string& path, std::string_view bytes, std::string format);

}  // namespace ricci::io
