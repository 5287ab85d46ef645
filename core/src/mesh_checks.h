// Helpers shared by the mesh checks of compact_mesh.cpp and triangulation.cpp (not installed API).
#pragma once

#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "ricci/errors.h"

namespace ricci::detail {

class UnionFind {
 public:
  explicit UnionFind(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(int a, int b) { parent_[find(a)] = find(b); }

 private:
  std::vector<int> parent_;
};

// "first: face 3, face 17, face 20" for up to three indices.
inline std::string first_indices(const std::string& what, const std::vector<int>& indices) {
  std::ostringstream s;
  s << "first: ";
  for (size_t i = 0; i < indices.size() && i < 3; ++i)
    s << (i ? ", " : "") << what << " " << indices[i];
  return s.str();
}

[[noreturn]] inline void fail(const std::string& fact, const std::string& where,
                              const std::string& todo) {
  throw InvalidMeshError("mesh: " + fact + " (" + where + "); " + todo);
}

}  // namespace ricci::detail
