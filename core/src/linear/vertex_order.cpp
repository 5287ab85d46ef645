#include "ricci/linear/vertex_order.h"

#include <algorithm>
#include <exception>
#include <system_error>
#include <utility>

#include <cholmod.h>

namespace ricci {

namespace detail {
std::mutex& nested_dissection_mutex() {
  static std::mutex m;
  return m;
}
}  // namespace detail

namespace {

// Per vertex its place in METIS's nested dissection order of the edge graph; empty on failure.
// The faces are taken by value: std::async keeps its copy of the arguments as long as the result,
// and this one is freed on return.
std::vector<int> order_edge_graph(int n, std::vector<std::array<int, 3>> faces,
                                  const std::function<void()>& finally) {
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
  faces = {};
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
    edges = {};
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
  if (finally) finally();
  return rank;
}

}  // namespace

VertexOrder VertexOrder::start(int num_vertices, const std::vector<std::array<int, 3>>& faces,
                               int from_vertices, std::function<void()> finally) {
  VertexOrder order;
  if (num_vertices < from_vertices || num_vertices <= 0) return order;
  try {
    order.rank_ =
        std::async(std::launch::async, order_edge_graph, num_vertices, faces, std::move(finally))
            .share();
  } catch (const std::system_error&) {
    return order;  // no thread to be had: each system finds its own ordering
  }
  order.num_ordered_ = num_vertices;
  return order;
}

VertexOrder VertexOrder::restricted(std::vector<int> from) const {
  if (empty()) return {};
  const int n = num_vertices();
  for (int& v : from) {
    if (v < 0 || v >= n) return {};
    if (from_) v = (*from_)[v];
  }
  VertexOrder order = *this;
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
  for (int v : *from_) out.push_back(rank[v]);
  return out;
}

std::vector<int> VertexOrder::rows(const std::vector<int>& row_of_vertex) const {
  if (empty() || static_cast<int>(row_of_vertex.size()) != num_vertices()) return {};
  std::vector<int> rank;
  try {
    rank = ranks();
  } catch (const std::exception&) {  // the ordering's thread failed (out of memory)
    return {};
  }
  if (rank.size() != row_of_vertex.size()) return {};  // METIS failed
  std::vector<std::pair<int, int>> ranked;             // (rank, vertex) of each vertex with a row
  for (size_t v = 0; v < row_of_vertex.size(); ++v)
    if (row_of_vertex[v] >= 0) ranked.emplace_back(rank[v], static_cast<int>(v));
  std::sort(ranked.begin(), ranked.end());
  std::vector<int> out;
  out.reserve(ranked.size());
  for (const auto& [r, v] : ranked) out.push_back(row_of_vertex[v]);
  return out;
}

}  // namespace ricci
