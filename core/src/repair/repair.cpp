#include "ricci/repair/repair.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "mesh/mesh_checks.h"
#include "repair/repair_steps.h"
#include "ricci/mesh/errors.h"

namespace ricci {

using detail::edge_key;
using detail::EdgeMap;
using detail::EdgeUses;
using detail::Face;
using detail::glued_pairs;
using detail::Reporter;
using detail::UnionFind;

namespace {

// === Fans and components

// Splits vertices into one per fan (corners joined across glued edges) and returns the faces on
// them; `components` joins the faces across glued edges. `cut_all`: edges whose faces stay apart.
std::vector<std::array<int, 3>> split_fans(const std::vector<Face>& faces, const EdgeMap& edges,
                                           const std::unordered_set<std::uint64_t>& cut_all,
                                           RepairedMesh& out, UnionFind& components,
                                           Reporter& reporter) {
  const int nf = static_cast<int>(faces.size());
  UnionFind corners(3 * nf);
  const auto corner = [&](int f, int v) {
    return 3 * f + static_cast<int>(std::find(faces[f].v.begin(), faces[f].v.end(), v) -
                                    faces[f].v.begin());
  };
  for (size_t e = 0; e < edges.num_edges(); ++e) {
    const std::uint64_t key = edges.key(e);
    const EdgeUses uses = edges.uses(e);
    if (uses.size() > 2) reporter.add("non-manifold edges cut open", "edge", uses[0].from);
    if (cut_all.count(key)) continue;
    for (const auto& [first, second] : glued_pairs(uses)) {
      components.unite(first.face, second.face);
      for (int v : {first.from, second.from}) {
        corners.unite(corner(first.face, v), corner(second.face, v));
      }
    }
  }
  std::vector<int> vertex_of_root(3 * nf, -1);
  std::vector<char> used(out.positions.size(), 0);
  std::vector<std::array<int, 3>> split(nf);
  for (int k = 0; k < 3 * nf; ++k) {
    const int v = faces[k / 3].v[k % 3], root = corners.find(k);
    if (vertex_of_root[root] < 0) {
      if (!used[v]) {
        vertex_of_root[root] = v;
        used[v] = 1;
      } else {
        reporter.add("non-manifold vertices split (a copy per fan of faces)", "vertex",
                     out.original[v]);
        vertex_of_root[root] = static_cast<int>(out.positions.size());
        out.positions.push_back(out.positions[v]);
        out.original.push_back(out.original[v]);
      }
    }
    split[k / 3][k % 3] = vertex_of_root[root];
  }
  return split;
}

// One vertex per fan of faces, and the components. Where faces of a non-manifold edge were paired
// but their fans joined again (so one component would still have the edge more than twice), all
// faces of that edge are cut apart and the split is redone.
void split_fans_and_components(const std::vector<Face>& faces, RepairedMesh& out,
                               Reporter& reporter) {
  const int nf = static_cast<int>(faces.size());
  const EdgeMap edges(faces);
  const size_t input_vertices = out.positions.size();
  std::unordered_set<std::uint64_t> cut_all;
  std::vector<std::array<int, 3>> split;
  UnionFind components(nf);
  for (int attempt = 0;; ++attempt) {
    out.positions.resize(input_vertices);
    out.original.resize(input_vertices);
    components = UnionFind(nf);
    Reporter attempt_reporter;
    split = split_fans(faces, edges, cut_all, out, components, attempt_reporter);
    // Without copies of vertices the split faces are the faces.
    std::optional<EdgeMap> split_map;
    if (out.positions.size() > input_vertices) {
      std::vector<Face> split_faces(nf);
      for (int f = 0; f < nf; ++f) split_faces[f] = {split[f], faces[f].input};
      split_map.emplace(split_faces);
    }
    const EdgeMap& split_edges = split_map ? *split_map : edges;
    const size_t before = cut_all.size();
    for (int f = 0; f < nf; ++f) {
      for (int c = 0; c < 3; ++c) {
        if (split_edges.uses(split_edges.edge_of(f, c)).size() > 2) {
          cut_all.insert(edge_key(faces[f].v[c], faces[f].v[(c + 1) % 3]));
        }
      }
    }
    if (cut_all.size() == before || attempt == 4) {
      reporter.merge(attempt_reporter);
      break;
    }
  }
  // Components in the order of their first input face.
  std::map<int, std::vector<int>> members;  // root -> faces
  for (int f = 0; f < nf; ++f) members[components.find(f)].push_back(f);
  std::vector<std::pair<int, std::vector<int>>> by_first;  // (first input face, faces)
  for (auto& [root, list] : members) {
    int first = faces[list[0]].input;
    for (int f : list) first = std::min(first, faces[f].input);
    by_first.emplace_back(first, std::move(list));
  }
  std::sort(by_first.begin(), by_first.end());
  std::vector<std::vector<int>> ordered;
  for (auto& [first, list] : by_first) ordered.push_back(std::move(list));
  std::vector<int> local(out.positions.size(), -1);
  for (const std::vector<int>& list : ordered) {
    // The component's vertices in increasing order.
    std::vector<int> vertices;
    for (int f : list) {
      for (int v : split[f]) {
        if (local[v] == -1) vertices.push_back(v), local[v] = -2;
      }
    }
    if (vertices.size() > out.positions.size() / 8) {
      vertices.clear();
      for (int v = 0; v < static_cast<int>(out.positions.size()); ++v) {
        if (local[v] == -2) vertices.push_back(v);
      }
    } else {
      std::sort(vertices.begin(), vertices.end());
    }
    std::vector<Eigen::Vector3d> positions;
    for (size_t i = 0; i < vertices.size(); ++i) {
      local[vertices[i]] = static_cast<int>(i);
      positions.push_back(out.positions[vertices[i]]);
    }
    std::vector<std::array<int, 3>> triangles;
    std::vector<int> input;
    for (int f : list) {
      triangles.push_back({local[split[f][0]], local[split[f][1]], local[split[f][2]]});
      input.push_back(faces[f].input);
    }
    try {
      out.components.push_back(
          {CompactMesh(std::move(positions), std::move(triangles)), vertices, input});
    } catch (const InvalidMeshError& e) {
      throw InvalidMeshError("component " + std::to_string(out.components.size()) +
                             " (with input face " + std::to_string(input[0]) + "): " + e.what());
    }
  }
}

}  // namespace

RepairedMesh repair_mesh(const std::vector<Eigen::Vector3d>& positions,
                         const std::vector<std::array<int, 3>>& faces,
                         const RepairOptions& options) {
  RepairedMesh out;
  const int n = static_cast<int>(positions.size());
  out.positions = positions;
  out.num_input_vertices = n;
  out.original.resize(n);
  std::iota(out.original.begin(), out.original.end(), 0);
  if (options.strict) {
    out.components.push_back({CompactMesh(positions, faces), out.original, {}});
    out.components[0].face.resize(faces.size());
    std::iota(out.components[0].face.begin(), out.components[0].face.end(), 0);
    out.represented_by = out.original;
    return out;
  }
  if (faces.empty()) throw InvalidMeshError("mesh: it has no faces; the flow needs a surface");
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int v : faces[f]) {
      if (v < 0 || v >= n) {
        throw InvalidMeshError("mesh: face " + std::to_string(f) + " refers to vertex " +
                               std::to_string(v) + ", which does not exist; re-export the file");
      }
      if (!positions[v].allFinite()) {
        throw InvalidMeshError("mesh: vertex " + std::to_string(v) + " of face " +
                               std::to_string(f) +
                               " has NaN or infinite coordinates; remove or repair it");
      }
    }
  }
  Reporter reporter;
  std::vector<int> welded;
  std::vector<Face> kept;
  // Vertices at one position are joined (unless the options keep the cuts), unless that makes a
  // component non-orientable (two sheets glued with a half twist): then the mesh is repaired again
  // with none of them joined.
  for (const bool join : {options.join_coincident, false}) {
    Reporter attempt;
    kept = drop_degenerate(positions, faces, welded, attempt, join);
    std::optional<RepairReport::Entry> joined;
    for (const RepairReport::Entry& e : attempt.report.entries) {
      if (e.what == detail::kJoinedVertices) joined = e;
    }
    try {
      orient(kept, attempt);
    } catch (const InvalidMeshError&) {
      if (!joined) throw;
      Reporter apart;
      apart.report.entries.push_back(
          {"vertices at one position all kept apart (joined, a component would not be "
           "orientable)",
           "vertex", joined->count, joined->first});
      reporter.merge(apart);
      continue;
    }
    reporter.merge(attempt);
    break;
  }
  remove_caps(positions, kept, reporter);
  if (kept.empty()) {
    throw InvalidMeshError("mesh: no face is left once degenerate faces are dropped");
  }
  split_fans_and_components(kept, out, reporter);
  std::vector<char> referenced(out.positions.size(), 0);
  for (const MeshComponent& c : out.components) {
    for (int v : c.vertex) referenced[v] = 1;
  }
  out.represented_by.assign(out.positions.size(), -1);
  for (size_t v = 0; v < out.positions.size(); ++v) {
    const int r = v < welded.size() ? welded[v] : static_cast<int>(v);
    if (referenced[r]) out.represented_by[v] = r;
  }
  // A vertex of a joined group (the one kept too) whose faces ended on another vertex of the
  // group's (a non-manifold edge cut open again onto copies) takes the results of the vertex that
  // holds its faces, itself where one of its faces is on it.
  std::vector<int> members(welded.size(), 0);
  for (int r : welded) ++members[r];
  std::vector<char> on_itself(welded.size(), 0);
  for (const MeshComponent& c : out.components) {
    for (size_t f = 0; f < c.face.size(); ++f) {
      for (int w : faces[c.face[f]]) {
        if (members[welded[w]] < 2 || on_itself[w]) continue;
        for (int k = 0; k < 3; ++k) {
          const int x = c.vertex[c.mesh.face_vertex(static_cast<int>(f), k)];
          if (out.original[x] != welded[w]) continue;
          out.represented_by[w] = x;
          on_itself[w] = x == w;
        }
      }
    }
  }
  for (int v = 0; v < n; ++v) {
    if (out.represented_by[v] < 0) {
      ++out.num_unreferenced;
      reporter.add("unreferenced vertices kept without a result", "vertex", v);
    }
  }
  out.report = std::move(reporter.report);
  return out;
}

}  // namespace ricci