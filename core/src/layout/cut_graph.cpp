#include "ricci/layout/cut_graph.h"

#include "layout/cut_graph.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace ricci {

namespace detail {

std::vector<int> prune_cut(const Triangulation& mesh, std::vector<char>& cut,
                           const std::vector<char>& keep) {
  const int ne = mesh.num_edges(), nv = mesh.num_vertices();
  std::vector<std::vector<int>> incident(nv);
  std::vector<int> degree(nv, 0);
  for (int e = 0; e < ne; ++e) {
    if (!cut[e] && !mesh.is_boundary_edge(e)) continue;
    for (int v : mesh.edge_vertices(e)) {
      incident[v].push_back(e);
      ++degree[v];
    }
  }
  std::vector<int> leaves;
  for (int v = 0; v < nv; ++v) {
    if (degree[v] == 1 && !(v < static_cast<int>(keep.size()) && keep[v])) leaves.push_back(v);
  }
  while (!leaves.empty()) {
    const int v = leaves.back();
    leaves.pop_back();
    if (degree[v] != 1) continue;
    for (int e : incident[v]) {
      if (!cut[e]) continue;
      cut[e] = 0;
      for (int w : mesh.edge_vertices(e)) {
        if (--degree[w] == 1 && !(w < static_cast<int>(keep.size()) && keep[w])) {
          leaves.push_back(w);
        }
      }
      break;
    }
  }
  return degree;
}

std::vector<CutPath> split_cut_into_paths(const Triangulation& mesh, const std::vector<char>& cut,
                                          const std::vector<int>& degree,
                                          const std::vector<char>& nodes) {
  const int ne = mesh.num_edges(), nv = mesh.num_vertices();
  std::vector<std::vector<int>> cut_at(nv);
  for (int e = 0; e < ne; ++e) {
    if (!cut[e]) continue;
    for (int v : mesh.edge_vertices(e)) cut_at[v].push_back(e);
  }
  const auto is_node = [&](int v) {
    return degree[v] != 2 || mesh.is_boundary_vertex(v) ||
           (v < static_cast<int>(nodes.size()) && nodes[v]);
  };
  std::vector<char> used(ne, 0);
  std::vector<CutPath> paths;
  const auto walk = [&](int start, int first_edge) {
    CutPath path;
    path.vertices.push_back(start);
    int v = start, e = first_edge;
    while (true) {
      used[e] = 1;
      path.edges.push_back(e);
      const auto [a, b] = mesh.edge_vertices(e);
      v = a == v ? b : a;
      path.vertices.push_back(v);
      if (is_node(v)) break;
      int next = -1;
      for (int f : cut_at[v]) {
        if (!used[f]) next = f;
      }
      if (next < 0) break;  // a closed loop without a node, back at start
      e = next;
    }
    paths.push_back(std::move(path));
  };
  for (int v = 0; v < nv; ++v) {
    if (!is_node(v)) continue;
    for (int e : cut_at[v]) {
      if (!used[e]) walk(v, e);
    }
  }
  for (int e = 0; e < ne; ++e) {  // loops through no node
    if (cut[e] && !used[e]) walk(mesh.edge_vertices(e)[0], e);
  }
  return paths;
}

}  // namespace detail

namespace {

// Every interior edge outside a breadth-first spanning tree of the dual graph, from face 0.
std::vector<char> dual_tree_complement(const Triangulation& mesh) {
  const int ne = mesh.num_edges(), nf = mesh.num_faces();
  std::vector<char> reached(nf, 0), in_tree(ne, 0), cut(ne, 0);
  std::queue<int> queue;
  queue.push(0);
  reached[0] = 1;
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop();
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * f + c);
      if (t < 0 || reached[t / 3]) continue;
      reached[t / 3] = 1;
      in_tree[mesh.face_edge(f, c)] = 1;
      queue.push(t / 3);
    }
  }
  for (int e = 0; e < ne; ++e) cut[e] = !mesh.is_boundary_edge(e) && !in_tree[e];
  return cut;
}

// Shortest distances over the dual graph from face `from` (a step between two faces weighs their
// mean side), and the edge each face was reached across (-1 at the root).
std::pair<std::vector<double>, std::vector<int>> dual_distances(const Triangulation& mesh,
                                                                const std::vector<double>& lengths,
                                                                int from) {
  const int nf = mesh.num_faces();
  std::vector<double> mean_side(nf), distance(nf, std::numeric_limits<double>::infinity());
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) mean_side[f] += lengths[mesh.face_edge(f, c)] / 3;
  }
  std::vector<int> reached_by(nf, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  distance[from] = 0;
  queue.push({0, from});
  while (!queue.empty()) {
    const auto [d, f] = queue.top();
    queue.pop();
    if (d > distance[f]) continue;
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * f + c);
      if (t < 0) continue;
      const int g = t / 3;
      const double via = d + 0.5 * (mean_side[f] + mean_side[g]);
      if (via < distance[g]) {
        distance[g] = via;
        reached_by[g] = mesh.face_edge(f, c);
        queue.push({via, g});
      }
    }
  }
  return {distance, reached_by};
}

// The cut from `cut` (a dual tree's complement): pruned and split into paths.
CutGraph finish(const Triangulation& mesh, std::vector<char> cut, int root) {
  CutGraph g;
  g.num_generators = 2 * mesh.genus() + std::max(0, mesh.num_boundary_loops() - 1);
  g.root = root;
  g.cut = std::move(cut);
  const std::vector<int> degree = detail::prune_cut(mesh, g.cut, {});
  g.paths = detail::split_cut_into_paths(mesh, g.cut, degree, {});
  return g;
}

}  // namespace

CutGraph cut_to_disk(const Triangulation& mesh) {
  if (mesh.num_faces() == 0) return finish(mesh, std::vector<char>(mesh.num_edges(), 0), 0);
  return finish(mesh, dual_tree_complement(mesh), 0);
}

CutGraph cut_to_disk(const Triangulation& mesh, const std::vector<double>& lengths) {
  if (mesh.num_faces() == 0) return finish(mesh, std::vector<char>(mesh.num_edges(), 0), 0);
  const auto farthest = [](const std::vector<double>& d) {
    return static_cast<int>(std::max_element(d.begin(), d.end()) - d.begin());
  };
  // Two sweeps: a face far from face 0, then the face farthest from it; the root is the face
  // nearest to both ends' midpoint (least max(d_a, d_b)).
  const int a = farthest(dual_distances(mesh, lengths, 0).first);
  const std::vector<double> from_a = dual_distances(mesh, lengths, a).first;
  const std::vector<double> from_b = dual_distances(mesh, lengths, farthest(from_a)).first;
  int root = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (std::max(from_a[f], from_b[f]) < std::max(from_a[root], from_b[root])) root = f;
  }
  const std::vector<int> reached_by = dual_distances(mesh, lengths, root).second;
  std::vector<char> in_tree(mesh.num_edges(), 0), cut(mesh.num_edges(), 0);
  for (int e : reached_by) {
    if (e >= 0) in_tree[e] = 1;
  }
  for (int e = 0; e < mesh.num_edges(); ++e) cut[e] = !mesh.is_boundary_edge(e) && !in_tree[e];
  return finish(mesh, std::move(cut), root);
}

}  // namespace ricci
