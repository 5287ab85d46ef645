#include "ricci/cut_graph.h"

#include <algorithm>
#include <queue>

namespace ricci {

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

// Glues back every cut edge with an end where no other cut or boundary edge meets, until none is
// left. Returns each vertex's number of cut and boundary edges.
std::vector<int> prune(const Triangulation& mesh, std::vector<char>& cut) {
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
    if (degree[v] == 1) leaves.push_back(v);
  }
  while (!leaves.empty()) {
    const int v = leaves.back();
    leaves.pop_back();
    if (degree[v] != 1) continue;
    for (int e : incident[v]) {
      if (!cut[e]) continue;
      cut[e] = 0;
      for (int w : mesh.edge_vertices(e)) {
        if (--degree[w] == 1) leaves.push_back(w);
      }
      break;
    }
  }
  return degree;
}

// The cut edges as paths between nodes (degree != 2 in the cut-and-boundary graph, or on the
// boundary), and loops through no node.
std::vector<CutPath> split_into_paths(const Triangulation& mesh, const std::vector<char>& cut,
                                      const std::vector<int>& degree) {
  const int ne = mesh.num_edges(), nv = mesh.num_vertices();
  std::vector<std::vector<int>> cut_at(nv);
  for (int e = 0; e < ne; ++e) {
    if (!cut[e]) continue;
    for (int v : mesh.edge_vertices(e)) cut_at[v].push_back(e);
  }
  const auto is_node = [&](int v) { return degree[v] != 2 || mesh.is_boundary_vertex(v); };
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

}  // namespace

CutGraph cut_to_disk(const Triangulation& mesh) {
  CutGraph g;
  g.num_generators = 2 * mesh.genus() + std::max(0, mesh.num_boundary_loops() - 1);
  g.cut.assign(mesh.num_edges(), 0);
  if (mesh.num_faces() == 0) return g;
  g.cut = dual_tree_complement(mesh);
  const std::vector<int> degree = prune(mesh, g.cut);
  g.paths = split_into_paths(mesh, g.cut, degree);
  return g;
}

}  // namespace ricci
