// Helpers shared by the mesh checks of compact_mesh.cpp and triangulation.cpp (not installed API).
#pragma once

#include <algorithm>
#include <array>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "ricci/mesh/errors.h"

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
//! (min(a, b), max(a, b), i): grouped by vertex pair, each group in item order. Two stable
//! counting sorts, by the larger vertex and then by the smaller: linear where a sort of 3 F keys
//! is not.
template <class Ends>
std::vector<int> order_by_vertex_pair(int num_vertices, int n, Ends ends) {
  std::vector<int> by_larger(n), order(n);
  std::vector<int> next(static_cast<size_t>(num_vertices) + 1);
  const auto counting_sort = [&](const auto& key, const auto& items, std::vector<int>& out) {
    std::fill(next.begin(), next.end(), 0);
    for (int k = 0; k < n; ++k) ++next[key(items(k)) + 1];
    std::partial_sum(next.begin(), next.end(), next.begin());
    for (int k = 0; k < n; ++k) {
      const int i = items(k);
      out[next[key(i)]++] = i;
    }
  };
  const auto larger = [&](int i) {
    const auto [a, b] = ends(i);
    return std::max(a, b);
  };
  const auto smaller = [&](int i) {
    const auto [a, b] = ends(i);
    return std::min(a, b);
  };
  counting_sort(
      larger, [](int k) { return k; }, by_larger);
  counting_sort(
      smaller, [&](int k) { return by_larger[k]; }, order);
  return order;
}

//! The items of 0..n-1 whose three vertices corners(i), as a set, an earlier item has too, in
//! increasing order. A counting sort by the smallest vertex, then the (small) buckets sorted.
template <class Corners>
std::vector<int> repeated_triangles(int num_vertices, int n, Corners corners) {
  const auto sorted = [&](int i) {
    std::array<int, 3> t = corners(i);
    std::sort(t.begin(), t.end());
    return t;
  };
  std::vector<int> start(static_cast<size_t>(num_vertices) + 1, 0);
  for (int i = 0; i < n; ++i) ++start[sorted(i)[0] + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int> order(n);
  std::vector<int> next(start.begin(), start.end() - 1);
  for (int i = 0; i < n; ++i) order[next[sorted(i)[0]]++] = i;
  std::vector<int> repeated;
  std::vector<std::pair<std::array<int, 3>, int>> bucket;
  for (int v = 0; v < num_vertices; ++v) {
    if (start[v + 1] - start[v] < 2) continue;
    bucket.clear();
    for (int k = start[v]; k < start[v + 1]; ++k) bucket.emplace_back(sorted(order[k]), order[k]);
    std::sort(bucket.begin(), bucket.end());
    for (size_t k = 1; k < bucket.size(); ++k) {
      if (bucket[k].first == bucket[k - 1].first) repeated.push_back(bucket[k].second);
    }
  }
  std::sort(repeated.begin(), repeated.end());
  return repeated;
}

[[noreturn]] inline void fail(const std::string& fact, const std::string& where,
                              const std::string& todo) {
  throw InvalidMeshError("mesh: " + fact + " (" + where + "); " + todo);
}

}  // namespace ricci::detail
