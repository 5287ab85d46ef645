#include "ricci/vertex_order.h"

#include <algorithm>
#include <utility>

#include <cholmod.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace ricci {

namespace detail {
std::mutex& nested_dissection_mutex() {
  static std::mutex m;
  return m;
}
}  // namespace detail

namespace {

// Per vertex its place in METIS's nested dissection order of the edge graph; empty on failure.
std::vector<int> order_edge_graph(int n, const std::vector<std::array<int, 3>>& faces) {
  // The upper triangle of the adjacency pattern, column by column.
  std::vector<std::pair<int, int>> edges;  // (column, row), row < column
  edges.reserve(3 * faces.size());
  for (const auto& f : faces) {
    bool valid = true;
    for (int c = 0; c < 3; ++c) valid = valid && f[c] >= 0 && f[c] < n && f[c] != f[(c + 1) % 3];
    if (!valid) continue;
    for (int c = 0; c < 3; ++c) {
      const int a = f[c], b = f[(c + 1) % 3];
      edges.emplace_back(std::max(a, b), std::min(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  std::vector<int> rank;
  cholmod_sparse* a =
      cholmod_allocate_sparse(n, n, edges.size(), true, true, 1, CHOLMOD_PATTERN, &common);
  if (a) {
    int* p = static_cast<int*>(a->p);
    int* i = static_cast<int*>(a->i);
    size_t e = 0;
    for (int col = 0; col < n; ++col) {
      p[col] = static_cast<int>(e);
      for (; e < edges.size() && edges[e].first == col; ++e) i[e] = edges[e].second;
    }
    p[n] = static_cast<int>(e);
    std::vector<int> perm(n);
    bool ok;
    {
      const std::lock_guard<std::mutex> lock(detail::nested_dissection_mutex());
      ok = cholmod_metis(a, nullptr, 0, false, perm.data(), &common);
    }
    if (ok) {
      rank.resize(n);
      for (int k = 0; k < n; ++k) rank[perm[k]] = k;
    }
    cholmod_free_sparse(&a, &common);
  }
  cholmod_finish(&common);
  edges = {};
#ifdef __GLIBC__
  // This thread's allocations came from a malloc arena of its own, which glibc would keep (the
  // command raises the trim threshold for its own loops): returned now, they do not add to the
  // run's peak memory.
  malloc_trim(0);
#endif
  return rank;
}

}  // namespace

VertexOrder VertexOrder::start(int num_vertices, const std::vector<std::array<int, 3>>& faces,
                               int from_vertices) {
  VertexOrder order;
  if (num_vertices < from_vertices || num_vertices <= 0) return order;
  order.rank_ = std::async(std::launch::async, order_edge_graph, num_vertices, faces).share();
  order.num_ordered_ = num_vertices;
  return order;
}

VertexOrder VertexOrder::restricted(std::vector<int> from) const {
  VertexOrder order = *this;
  if (empty()) return order;
  if (from_) {
    for (int& v : from) v = (*from_)[v];
  }
  order.from_ = std::make_shared<const std::vector<int>>(std::move(from));
  return order;
}

int VertexOrder::num_vertices() const {
  if (empty()) return 0;
  return from_ ? static_cast<int>(from_->size()) : num_ordered_;
}

std::vector<int> VertexOrder::ranks() const {
  const std::vector<int>& rank = rank_.get();
  if (!from_ || rank.empty()) return rank;
  std::vector<int> out;
  out.reserve(from_->size());
  for (int v : *from_) out.push_back(v >= 0 && v < static_cast<int>(rank.size()) ? rank[v] : 0);
  return out;
}

}  // namespace ricci
