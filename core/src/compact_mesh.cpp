#include "ricci/compact_mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>
#include <utility>

#include "ricci/errors.h"

namespace ricci {

namespace {

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
std::string first_indices(const std::string& what, const std::vector<int>& indices) {
  std::ostringstream s;
  s << "first: ";
  for (size_t i = 0; i < indices.size() && i < 3; ++i) s << (i ? ", " : "") << what << " " << indices[i];
  return s.str();
}

[[noreturn]] void fail(const std::string& fact, const std::string& where, const std::string& todo) {
  throw InvalidMeshError("mesh: " + fact + " (" + where + "); " + todo);
}

}  // namespace

CompactMesh::CompactMesh(std::vector<Eigen::Vector3d> positions,
                         std::vector<std::array<int, 3>> faces)
    : positions_(std::move(positions)), faces_(std::move(faces)) {
  check_elements();
  build_edges();
  check_manifold_vertices();
  check_connected();
  build_boundary_loops();
}

void CompactMesh::check_elements() {
  const int n = num_vertices();
  if (n == 0 || faces_.empty()) {
    throw InvalidMeshError("mesh: it has " + std::to_string(n) + " vertices and " +
                           std::to_string(faces_.size()) +
                           " faces; the flow needs a triangle mesh with at least one face");
  }
  std::vector<int> bad;
  for (int v = 0; v < n; ++v) {
    if (!positions_[v].allFinite()) bad.push_back(v);
  }
  if (!bad.empty()) {
    fail(std::to_string(bad.size()) + " vertices have NaN or infinite coordinates",
         first_indices("vertex", bad), "remove or repair them before running the flow");
  }
  for (int f = 0; f < num_faces(); ++f) {
    for (int v : faces_[f]) {
      if (v < 0 || v >= n) bad.push_back(f);
    }
  }
  if (!bad.empty()) {
    fail(std::to_string(bad.size()) + " faces reference vertices that do not exist",
         first_indices("face", bad), "the file is corrupt; re-export it");
  }
  std::vector<int> degenerate;
  for (int f = 0; f < num_faces(); ++f) {
    const auto& t = faces_[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      degenerate.push_back(f);
      continue;
    }
    const Eigen::Vector3d& p0 = positions_[t[0]];
    const Eigen::Vector3d e1 = positions_[t[1]] - p0, e2 = positions_[t[2]] - p0;
    const double longest = std::max({e1.squaredNorm(), e2.squaredNorm(),
                                     (positions_[t[2]] - positions_[t[1]]).squaredNorm()});
    // Twice the area against the longest edle squared: 0 for collinear corners.
    if (!(e1.cross(e2).norm() > 1e-12 * longest)) degenerate.push_back(f);
  }
  if (!degenerate.empty()) {
    fail(std::to_string(degenerate.size()) + " degenerate faces (zero area or repeated vertex)",
         first_indices("face", degenerate),
         "remove them, e.g. MeshLab's Filters > Cleaning and Repairing > Remove Zero Area Faces");
  }
  std::vector<char> referenced(n, 0);
  for (const auto& t : faces_) {
    for (int v : t) referenced[v] = 1;
  }
  for (int v = 0; v < n; ++v) {
    if (!referenced[v]) bad.push_back(v);
  }
  if (!bad.empty()) {
    fail(std::to_string(bad.size()) + " unreferenced vertices", first_indices("vertex", bad),
         "remove them, e.g. MeshLab's Filters > Cleaning and Repairing > Remove Unreferenced "
         "Vertices");
  }
  std::map<std::array<int, 3>, int> seen;
  std::vector<int> duplicates;
  for (int f = 0; f < num_faces(); ++f) {
    std::array<int, 3> key = faces_[f];
    std::sort(key.begin(), key.end());
    auto [it, inserted] = seen.emplace(key, f);
    if (!inserted) duplicates.push_back(f);
  }
  if (!duplicates.empty()) {
    fail(std::to_string(duplicates.size()) + " duplicate faces (same three vertices as another)",
         first_indices("face", duplicates),
         "remove them, e.g. MeshLab's Filters > Cleaning and Repairing > Remove Duplicate Faces");
  }
}

void CompactMesh::build_edges() {
  const int nf = num_faces();
  face_edges_.assign(nf, {-1, -1, -1});
  twin_.assign(3 * nf, -1);
  std::map<std::pair<int, int>, int> edge_of;  // (min, max) vertex -> edge
  std::vector<int> first_halfedge;             // first halfedge seen for each edge
  std::vector<int> nonmanifold, misoriented;
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int h = 3 * f + c;
      const int a = halfedge_tail(h), b = halfedge_head(h);
      const std::pair<int, int> key(std::min(a, b), std::max(a, b));
      auto it = edge_of.find(key);
      if (it == edge_of.end()) {
        const int e = num_edges();
        edge_of.emplace(key, e);
        edge_vertices_.push_back({key.first, key.second});
        edge_faces_.push_back({f, -1});
        first_halfedge.push_back(h);
        face_edges_[f][c] = e;
        continue;
      }
      const int e = it->second;
      face_edges_[f][c] = e;
      if (edge_faces_[e][1] >= 0) {
        nonmanifold.push_back(e);
        continue;
      }
      const int g = first_halfedge[e];
      if (halfedge_tail(g) == a) misoriented.push_back(e);
      edge_faces_[e][1] = f;
      twin_[h] = g;
      twin_[g] = h;
    }
  }
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
    fail(std::to_string(nonmanifold.size()) + " non-manifold edges (shared by more than two faces)",
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
  input_lengths_.resize(num_edges());
  for (int e = 0; e < num_edges(); ++e) {
    input_lengths_[e] = (positions_[edge_vertices_[e][0]] - positions_[edge_vertices_[e][1]]).norm();
  }
  boundary_vertex_.assign(num_vertices(), 0);
  for (int e = 0; e < num_edges(); ++e) {
    if (is_boundary_edge(e)) boundary_vertex_[edge_vertices_[e][0]] = boundary_vertex_[edge_vertices_[e][1]] = 1;
  }
}

void CompactMesh::check_manifold_vertices() {
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

void CompactMesh::check_connected() {
  UnionFind vertices(num_vertices());
  for (const auto& t : faces_) {
    vertices.unite(t[0], t[1]);
    vertices.unite(t[1], t[2]);
  }
  std::map<int, int> size_of_component;
  for (int v = 0; v < num_vertices(); ++v) ++size_of_component[vertices.find(v)];
  if (size_of_component.size() > 1) {
    std::vector<int> sizes;
    for (const auto& [root, size] : size_of_component) sizes.push_back(size);
    std::sort(sizes.rbegin(), sizes.rend());
    std::ostringstream s;
    s << "vertex counts of the largest: ";
    for (size_t i = 0; i < sizes.size() && i < 3; ++i) s << (i ? ", " : "") << sizes[i];
    fail(std::to_string(size_of_component.size()) + " connected components", s.str(),
         "the flow runs on one component: keep the one you want, e.g. MeshLab's Filters > "
         "Cleaning and Repairing > Remove Isolated pieces, or split them into layers");
  }
}

void CompactMesh::build_boundary_loops() {
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

double CompactMesh::input_area() const {
  double area = 0;
  for (const auto& t : faces_) {
    area += 0.5 * (positions_[t[1]] - positions_[t[0]]).cross(positions_[t[2]] - positions_[t[0]]).norm();
  }
  return area;
}

std::string CompactMesh::topology_name() const {
  const int g = genus(), b = num_boundary_loops();
  if (b == 0) return "closed genus-" + std::to_string(g) + " surface";
  if (g == 0 && b == 1) return "disk";
  return "genus-" + std::to_string(g) + " surface with " + std::to_string(b) + " boundary loops";
}

}  // namespace ricci
