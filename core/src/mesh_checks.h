// Helpers shared by the mesh checks of compact_mesh.cpp and triangulation.cpp (not installed API).
#pragma once

#include <algorithm>
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

//! The items 0..n-1, each an edge between vertices ends(i) = {a, b} (a != b or not), ordered by
//! (min(a, b), max(a, b), i): grouped by vertex pair, each group in item order. A counting sort
//! by the smaller vertex, then the (small) buckets sorted; linear where a sort of 3 F keys is not.
template <class Ends>
std::vector<int> order_by_vertex_pair(int num_vertices, int n, Ends ends) {
  std::vector<int> start(static_cast<size_t>(num_vertices) + 1, 0);
  for (int i = 0; i < n; ++i) {
    const auto [a, b] = ends(i);
    ++start[std::min(a, b) + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int> order(n);
  std::vector<int> next(start.begin(), start.end() - 1);
  for (int i = 0; i < n; ++i) {
    const auto [a, b] = ends(i);
    order[next[std::min(a, b)]++] = i;
  }
  const auto larger = [&](int i) {
    const auto [a, b] = ends(i);
    return std::max(a, b);
  };
  for (int v = 0; v < num_vertices; ++v) {
    // Items were placed in increasing order: a stable sort by the larger vertex keeps it.
    std::stable_sort(order.begin() + start[v], order.begin() + start[v + 1],
                     [&](int i, int j) { return larger(i) < larger(j); });
  }
  return order;
}

[[noreturn]] inline void fail(const std::string& fact, const std::string& where,
                              const std::string& todo) {
  throw InvalidMeshError("mesh: " + fact + " (" + where + "); " + todo);
}

}  // namespace ricci::detail
