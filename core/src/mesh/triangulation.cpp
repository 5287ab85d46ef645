#include "ricci/mesh/triangulation.h"

#include <algorithm>
#include <cstdint>
#include <sstream>
#include <utility>

#include "mesh/mesh_checks.h"

namespace ricci {

using detail::fail;
using detail::first_indices;
using detail::order_by_vertex_pair;
using detail::UnionFind;

Triangulation Triangulation::from_faces(int num_vertices, std::vector<std::array<int, 3>> faces) {
  Triangulation t;
  t.faces_ = std::move(faces);
  t.build_connectivity(num_vertices);
  return t;
}

void Triangulation::build_connectivity(int num_vertices) {
  connect(num_vertices, nullptr, num_vertices);
}

void Triangulation::build_connectivity(int num_vertices,
                                       const std::vector<std::array<int, 2>>& halfedge_keys,
                                       int num_keys) {
  connect(num_vertices, &halfedge_keys, num_keys);
}

void Triangulation::connect(int num_vertices, const std::vector<std::array<int, 2>>* keys,
                            int num_keys) {
  num_vertices_ = num_vertices;
  build_edges(keys, num_keys);
  check_manifold_vertices();
  check_connected();
  build_boundary_loops();
}

void Triangulation::build_edges(const std::vector<std::array<int, 2>>* keys, int num_keys) {
  const int nf = num_faces();
  face_edges_.assign(nf, {-1, -1, -1});
  twin_.assign(3 * nf, -1);
  const auto ends = [&](int h) {
    return keys ? (*keys)[h] : std::array<int, 2>{halfedge_tail(h), halfedge_head(h)};
  };
  // Halfedges grouped by their keys (vertex pair), each group in index order, its first halfedge
  // first. Edges are numbered in the order their first halfedge comes (faces, then corners).
  const std::vector<int> by_pair = order_by_vertex_pair(num_keys, 3 * nf, ends);
  const auto same_pair = [&](int g, int h) {
    const auto [a, b] = ends(g);
    const auto [c, d] = ends(h);
    return std::min(a, b) == std::min(c, d) && std::max(a, b) == std::max(c, d);
  };
  // The position in by_pair of each group's first halfedge, indexed by that halfedge (else -1).
  std::vector<int> group_at(3 * static_cast<size_t>(nf), -1);
  int num_groups = 0;
  for (size_t i = 0; i < by_pair.size(); ++i) {
    if (i == 0 || !same_pair(by_pair[i], by_pair[i - 1])) {
      group_at[by_pair[i]] = static_cast<int>(i);
      ++num_groups;
    }
  }
  edge_vertices_.reserve(num_groups);
  edge_faces_.reserve(num_groups);
  std::vector<std::pair<int, int>> nonmanifold_at, misoriented_at;  // (halfedge, edge)
  for (int first = 0; first < 3 * nf; ++first) {
    if (group_at[first] < 0) continue;
    const size_t position = group_at[first];
    const int e = num_edges();
    const int a = halfedge_tail(first), b = halfedge_head(first);
    edge_vertices_.push_back({std::min(a, b), std::max(a, b)});
    edge_faces_.push_back({first / 3, -1});
    face_edges_[first / 3][first % 3] = e;
    for (size_t i = position + 1; i < by_pair.size() && same_pair(by_pair[i], first); ++i) {
      const int h = by_pair[i];
      face_edges_[h / 3][h % 3] = e;
      if (edge_faces_[e][1] >= 0) {
        nonmanifold_at.emplace_back(h, e);
        continue;
      }
      if (ends(first)[0] == ends(h)[0]) misoriented_at.emplace_back(h, e);
      edge_faces_[e][1] = h / 3;
      twin_[h] = first;
      twin_[first] = h;
    }
  }
  // In the order the halfedges come, as a walk over the faces meets them.
  const auto edges_of = [](std::vector<std::pair<int, int>> at) {
    std::sort(at.begin(), at.end());
    std::vector<int> edges;
    for (const auto& [h, e] : at) edges.push_back(e);
    return edges;
  };
  std::vector<int> nonmanifold = edges_of(nonmanifold_at), misoriented = edges_of(misoriented_at);
  auto edge_names = [&](const std::vector<int>& edges) {
    std::ostringstream s;
    s << "first: ";
    for (size_t i = 0; i < edges.size() && i < 3; ++i) {
      s << (i ? ", " : "") << "edge (" << edge_vertices_[edges[i]][0] << ", "
        << edge_vertices_[edges[i]][1] << ")";
    }
    return s.str();
  };
  if (!nonmanifold.empty()) {
    std::sort(nonmanifold.begin(), nonmanifold.end());
    nonmanifold.erase(std::unique(nonmanifold.begin(), nonmanifold.end()), nonmanifold.end());
    fail(
        std::to_string(nonmanifold.size()) + " non-manifold edges (shared by more than two faces)",
        edge_names(nonmanifold),
        "repair them, e.g. MeshLab's Filters > Cleaning and Repairing > Repair non Manifold Edges");
  }
  if (!misoriented.empty()) {
    fail(std::to_string(misoriented.size()) +
             " edges where the two faces have opposite orientations (or the surface is not "
             "orientable)",
         edge_names(misoriented),
         "reorient the faces coherently, e.g. MeshLab's Filters > Normals > Re-Orient all faces "
         "coherently; a non-orientable surface cannot be used");
  }
  boundary_vertex_.assign(num_vertices(), 0);
  for (int e = 0; e < num_edges(); ++e) {
    if (is_boundary_edge(e))
      boundary_vertex_[edge_vertices_[e][0]] = boundary_vertex_[edge_vertices_[e][1]] = 1;
  }
}

void Triangulation::check_manifold_vertices() {
  // Corners around a vertex are joined across interior edges; a manifold vertex has one fan.
  const int nf = num_faces();
  UnionFind corners(3 * nf);
  for (int h = 0; h < 3 * nf; ++h) {
    const int t = twin_[h];
    if (t < h) continue;
    const int f = h / 3, g = t / 3;
    for (int side = 0; side < 2; ++side) {
      const int v = side == 0 ? halfedge_tail(h) : halfedge_head(h);
      int cf = 0, cg = 0;
      while (faces_[f][cf] != v) ++cf;
      while (faces_[g][cg] != v) ++cg;
      corners.unite(3 * f + cf, 3 * g + cg);
    }
  }
  std::vector<int> fan(num_vertices(), -1);
  std::vector<int> bad;
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = faces_[f][c];
      const int root = corners.find(3 * f + c);
      if (fan[v] < 0) {
        fan[v] = root;
      } else if (fan[v] != root && (bad.empty() || bad.back() != v)) {
        bad.push_back(v);
      }
    }
  }
  std::sort(bad.begin(), bad.end());
  bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
  if (!bad.empty()) {
    fail(std::to_string(bad.size()) + " non-manifold vertices (their faces form several fans)",
         first_indices("vertex", bad),
         "repair them, e.g. MeshLab's Filters > Cleaning and Repairing > Split Vertices on "
         "non Manifold Vertices");
  }
}

void Triangulation::check_connected() {
  UnionFind vertices(num_vertices());
  for (const auto& t : faces_) {
    vertices.unite(t[0], t[1]);
    vertices.unite(t[1], t[2]);
  }
  std::vector<int> size_of_root(num_vertices(), 0);
  for (int v = 0; v < num_vertices(); ++v) ++size_of_root[vertices.find(v)];
  std::vector<int> sizes;
  for (int size : size_of_root) {
    if (size > 0) sizes.push_back(size);
  }
  if (sizes.size() > 1) {
    std::sort(sizes.rbegin(), sizes.rend());
    std::ostringstream s;
    s << "vertex counts of the largest: ";
    for (size_t i = 0; i < sizes.size() && i < 3; ++i) s << (i ? ", " : "") << sizes[i];
    fail(std::to_string(sizes.size()) + " connected components", s.str(),
         "the flow runs on one component: keep the one you want, e.g. MeshLab's Filters > "
         "Cleaning and Repairing > Remove Isolated pieces, or split them into layers");
  }
}

void Triangulation::build_boundary_loops() {
  // On a manifold mesh every boundary vertex has exactly one outgoing boundary halfedge.
  std::vector<int> next(num_vertices(), -1);
  for (int h = 0; h < num_halfedges(); ++h) {
    if (twin_[h] < 0) next[halfedge_tail(h)] = halfedge_head(h);
  }
  std::vector<char> visited(num_vertices(), 0);
  for (int v = 0; v < num_vertices(); ++v) {
    if (next[v] < 0 || visited[v]) continue;
    std::vector<int> loop;
    for (int w = v; !visited[w]; w = next[w]) {
      visited[w] = 1;
      loop.push_back(w);
    }
    boundary_loops_.push_back(std::move(loop));
  }
}

int Triangulation::edge_halfedge(int e) const {
  const int f = edge_faces_[e][0];
  for (int c = 0; c < 3; ++c) {
    if (face_edges_[f][c] == e) return 3 * f + c;
  }
  return -1;
}

std::array<int, 2> Triangulation::opposite_vertices(int e) const {
  const int h = edge_halfedge(e), t = twin_[h];
  return {faces_[h / 3][h % 3], t < 0 ? -1 : faces_[t / 3][t % 3]};
}

void Triangulation::link_twins(int e) {
  int halfedge[2] = {-1, -1};
  for (int side = 0; side < 2; ++side) {
    const int f = edge_faces_[e][side];
    if (f < 0) continue;
    for (int c = 0; c < 3; ++c) {
      if (face_edges_[f][c] == e) halfedge[side] = 3 * f + c;
    }
  }
  if (halfedge[0] >= 0) twin_[halfedge[0]] = halfedge[1];
  if (halfedge[1] >= 0) twin_[halfedge[1]] = halfedge[0];
}

bool Triangulation::flips_to_triangles(int e) const {
  if (is_boundary_edge(e)) return false;
  const int h = edge_halfedge(e), t = twin_[h];
  const int f = h / 3, c = h % 3, g = t / 3, d = t % 3;
  if (f == g) return false;
  std::array<int, 4> sides = {face_edges_[f][(c + 1) % 3], face_edges_[f][(c + 2) % 3],
                              face_edges_[g][(d + 1) % 3], face_edges_[g][(d + 2) % 3]};
  std::sort(sides.begin(), sides.end());
  return std::adjacent_find(sides.begin(), sides.end()) == sides.end();
}

bool Triangulation::flip(int e) {
  if (!flips_to_triangles(e)) return false;
  const int h = edge_halfedge(e), t = twin_[h];
  const int f = h / 3, c = h % 3, g = t / 3, d = t % 3;
  // Face f = (k, a, b) and face g = (l, b, a), both counter-clockwise: the quad is k, a, l, b.
  const int k = faces_[f][c], a = faces_[f][(c + 1) % 3], b = faces_[f][(c + 2) % 3];
  const int l = faces_[g][d];
  const int e_bk = face_edges_[f][(c + 1) % 3], e_ka = face_edges_[f][(c + 2) % 3];
  const int e_al = face_edges_[g][(d + 1) % 3], e_lb = face_edges_[g][(d + 2) % 3];
  // New faces (k, a, l) and (l, b, k), each listing the edge opposite each corner.
  faces_[f] = {k, a, l};
  face_edges_[f] = {e_al, e, e_ka};
  faces_[g] = {l, b, k};
  face_edges_[g] = {e_bk, e, e_lb};
  edge_vertices_[e] = {std::min(k, l), std::max(k, l)};
  auto replace_face = [&](int edge, int from, int to) {
    for (int& x : edge_faces_[edge]) {
      if (x == from) {
        x = to;
        return;
      }
    }
  };
  replace_face(e_al, g, f);
  replace_face(e_bk, f, g);
  for (int edge : {e, e_al, e_bk, e_ka, e_lb}) link_twins(edge);
  return true;
}

std::string Triangulation::topology_name() const {
  const int g = genus(), b = num_boundary_loops();
  if (b == 0) return "closed genus-" + std::to_string(g) + " surface";
  if (g == 0 && b == 1) return "disk";
  return "genus-" + std::to_string(g) + " surface with " + std::to_string(b) + " boundary loops";
}

}  // namespace ricci
