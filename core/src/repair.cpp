#include "ricci/repair.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "mesh_checks.h"
#include "ricci/errors.h"

namespace ricci {

namespace {

using detail::UnionFind;

struct Face {
  std::array<int, 3> v;
  int input;  // the input face it lies in
};

// Collects the report's entries in the order they first happen.
class Reporter {
 public:
  void add(const std::string& what, const std::string& element, int index) {
    auto it = std::find_if(report.entries.begin(), report.entries.end(),
                           [&](const RepairReport::Entry& e) { return e.what == what; });
    if (it == report.entries.end()) {
      report.entries.push_back({what, element, 0, {}});
      it = report.entries.end() - 1;
    }
    ++it->count;
    if (it->first.size() < 3) it->first.push_back(index);
  }
  void merge(const Reporter& other) {
    for (const RepairReport::Entry& e : other.report.entries) {
      for (int index : e.first) add(e.what, e.element, index);
      auto it = std::find_if(report.entries.begin(), report.entries.end(),
                             [&](const RepairReport::Entry& x) { return x.what == e.what; });
      it->count += e.count - static_cast<int>(e.first.size());
    }
  }
  RepairReport report;
};

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return lo << 32 | hi;
}

// A face's use of an edge: the face traverses it from `from` (corner order v0 -> v1 -> v2 -> v0).
struct EdgeUse {
  int face;
  int from;
};
using EdgeMap = std::unordered_map<std::uint64_t, std::vector<EdgeUse>>;

EdgeMap edge_uses(const std::vector<Face>& faces) {
  EdgeMap edges;
  edges.reserve(3 * faces.size());
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    const auto& v = faces[f].v;
    for (int c = 0; c < 3; ++c) edges[edge_key(v[c], v[(c + 1) % 3])].push_back({f, v[c]});
  }
  return edges;
}

// The pairs of faces glued across an edge: two faces that traverse it in opposite ways. Where more
// than two faces share the edge (non-manifold), they are paired in file order and the rest cut
// off.
std::vector<std::pair<EdgeUse, EdgeUse>> glued_pairs(const std::vector<EdgeUse>& uses) {
  std::vector<std::pair<EdgeUse, EdgeUse>> pairs;
  std::vector<char> paired(uses.size(), 0);
  for (size_t i = 0; i < uses.size(); ++i) {
    for (size_t j = i + 1; j < uses.size() && !paired[i]; ++j) {
      if (paired[j] || uses[j].from == uses[i].from) continue;
      pairs.emplace_back(uses[i], uses[j]);
      paired[i] = paired[j] = 1;
    }
  }
  return pairs;
}

// === Needles, repeated vertices, duplicates

// Collapses edges of zero length (relative to the mesh's size), drops the faces that then repeat
// a vertex, and exact duplicates. `represented_by` receives each vertex's surviving vertex.
std::vector<Face> drop_degenerate(const std::vector<Eigen::Vector3d>& p,
                                  const std::vector<std::array<int, 3>>& input,
                                  std::vector<int>& represented_by, Reporter& reporter) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (const auto& t : input) {
    for (int v : t) lo = lo.cwiseMin(p[v]), hi = hi.cwiseMax(p[v]);
  }
  const double needle = 1e-12 * (hi - lo).norm();
  const int n = static_cast<int>(p.size());
  UnionFind weld(n);
  for (const auto& t : input) {
    for (int c = 0; c < 3; ++c) {
      const int a = t[c], b = t[(c + 1) % 3];
      if (a != b && (p[a] - p[b]).norm() <= needle && weld.find(a) != weld.find(b)) {
        reporter.add("zero-length edges collapsed", "edge", std::min(a, b));
        weld.unite(a, b);
      }
    }
  }
  std::vector<int> smallest(n, n);
  for (int v = 0; v < n; ++v) smallest[weld.find(v)] = std::min(smallest[weld.find(v)], v);
  represented_by.resize(n);
  for (int v = 0; v < n; ++v) represented_by[v] = smallest[weld.find(v)];
  std::vector<Face> faces;
  std::map<std::array<int, 3>, int> seen;
  for (int f = 0; f < static_cast<int>(input.size()); ++f) {
    Face face{
        {represented_by[input[f][0]], represented_by[input[f][1]], represented_by[input[f][2]]}, f};
    const auto& v = face.v;
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) {
      reporter.add("faces with a repeated vertex dropped", "face", f);
      continue;
    }
    std::array<int, 3> key = v;
    std::sort(key.begin(), key.end());
    if (!seen.emplace(key, f).second) {
      reporter.add("duplicate faces dropped", "face", f);
      continue;
    }
    faces.push_back(face);
  }
  return faces;
}

// === Orientation

// Makes the orientation agree across every glued edge, keeping each component's majority.
// \throws InvalidMeshError for a component that is not orientable.
void orient(std::vector<Face>& faces, Reporter& reporter) {
  const int nf = static_cast<int>(faces.size());
  const EdgeMap edges = edge_uses(faces);
  std::vector<int> component(nf, -1);
  std::vector<char> flipped(nf, 0);
  const auto effective_from = [&](const EdgeUse& use, int a, int b) {
    return flipped[use.face] ? (use.from == a ? b : a) : use.from;
  };
  int num_components = 0;
  for (int seed = 0; seed < nf; ++seed) {
    if (component[seed] >= 0) continue;
    std::vector<int> members = {seed};
    component[seed] = num_components;
    for (size_t k = 0; k < members.size(); ++k) {
      const int f = members[k];
      for (int c = 0; c < 3; ++c) {
        const int a = faces[f].v[c], b = faces[f].v[(c + 1) % 3];
        const std::vector<EdgeUse>& uses = edges.at(edge_key(a, b));
        if (uses.size() != 2) continue;  // boundary or non-manifold: not glued
        const EdgeUse& mine = uses[0].face == f ? uses[0] : uses[1];
        const EdgeUse& other = uses[0].face == f ? uses[1] : uses[0];
        const int g = other.face;
        const bool agree = effective_from(mine, a, b) != other.from;
        if (component[g] < 0) {
          component[g] = num_components;
          flipped[g] = !agree;
          members.push_back(g);
        } else if (effective_from(mine, a, b) == effective_from(other, a, b)) {
          throw InvalidMeshError(
              "mesh: the surface of face " + std::to_string(faces[f].input) +
              " is not orientable (a Moebius strip, a Klein bottle, ...): it has no conformal map "
              "to the plane, the disk or the sphere; orientable components can be used on their "
              "own (e.g. MeshLab's Filters > Selection > Select Connected Faces, then Delete)");
        }
      }
    }
    const auto count =
        std::count_if(members.begin(), members.end(), [&](int f) { return flipped[f] != 0; });
    const bool invert = 2 * count > static_cast<long>(members.size());
    for (int f : members) {
      if ((flipped[f] != 0) == invert) continue;
      std::swap(faces[f].v[1], faces[f].v[2]);
      reporter.add("faces reoriented to agree with their neighbours", "face", faces[f].input);
    }
    ++num_components;
  }
}

// === Caps

// The corner of a zero-area face whose vertex lies inside the opposite (longest) edge, or -1.
int cap_corner(const std::vector<Eigen::Vector3d>& p, const Face& f) {
  const Eigen::Vector3d& a = p[f.v[0]];
  const Eigen::Vector3d e1 = p[f.v[1]] - a, e2 = p[f.v[2]] - a;
  const std::array<double, 3> opposite = {(p[f.v[2]] - p[f.v[1]]).squaredNorm(), e2.squaredNorm(),
                                          e1.squaredNorm()};
  const int c =
      static_cast<int>(std::max_element(opposite.begin(), opposite.end()) - opposite.begin());
  // The same test as CompactMesh's: twice the area against the longest edge squared.
  return e1.cross(e2).norm() > 1e-12 * opposite[c] ? -1 : c;
}

// Removes caps: the face across the cap's longest edge is split at the cap's middle vertex (the two
// halves tile it), and the cap dropped; a cap on the boundary is dropped.
void remove_caps(const std::vector<Eigen::Vector3d>& p, std::vector<Face>& faces,
                 Reporter& reporter) {
  for (int pass = 0; pass < 20; ++pass) {
    const EdgeMap edges = edge_uses(faces);
    std::vector<char> touched(faces.size(), 0), dropped(faces.size(), 0);
    std::vector<Face> added;
    for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
      const int c = cap_corner(p, faces[f]);
      if (c < 0 || touched[f]) continue;
      const int m = faces[f].v[c], a = faces[f].v[(c + 1) % 3], b = faces[f].v[(c + 2) % 3];
      const std::vector<EdgeUse>& uses = edges.at(edge_key(a, b));
      const EdgeUse* across = nullptr;
      for (const EdgeUse& u : uses) {
        if (u.face != f) across = &u;
      }
      if (uses.size() == 2 && touched[across->face]) continue;  // next pass
      touched[f] = dropped[f] = 1;
      reporter.add("zero-area faces removed (the face across the longest edge split)", "face",
                   faces[f].input);
      if (uses.size() != 2 || across->from != b) continue;  // boundary (or non-manifold): dropped
      Face& g = faces[across->face];
      touched[across->face] = 1;
      int d = g.v[0];
      for (int v : g.v) {
        if (v != a && v != b) d = v;
      }
      added.push_back({{m, a, d}, g.input});  // g runs b -> a -> d; m lies on b -> a
      g.v = {b, m, d};
    }
    if (added.empty() && std::none_of(dropped.begin(), dropped.end(), [](char x) { return x; })) {
      return;
    }
    std::vector<Face> kept;
    for (size_t f = 0; f < faces.size(); ++f) {
      if (!dropped[f]) kept.push_back(faces[f]);
    }
    kept.insert(kept.end(), added.begin(), added.end());
    faces = std::move(kept);
  }
}

}  // namespace

std::vector<std::string> RepairReport::lines() const {
  std::vector<std::string> out;
  for (const Entry& e : entries) {
    std::ostringstream s;
    s << e.count << " " << e.what << " (" << detail::first_indices(e.element, e.first) << ")";
    out.push_back(s.str());
  }
  return out;
}

namespace {

// === Fans and components

// One vertex per fan of faces: corners are joined across glued edges; a vertex with several
// fans gets a copy per further fan. Then the faces' components.
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
  for (const auto& [key, uses] : edges) {
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
  const EdgeMap edges = edge_uses(faces);
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
    std::unordered_map<std::uint64_t, int> faces_at;
    for (const auto& t : split) {
      for (int c = 0; c < 3; ++c) ++faces_at[edge_key(t[c], t[(c + 1) % 3])];
    }
    const size_t before = cut_all.size();
    for (int f = 0; f < nf; ++f) {
      for (int c = 0; c < 3; ++c) {
        if (faces_at[edge_key(split[f][c], split[f][(c + 1) % 3])] > 2) {
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
    std::vector<int> vertices;
    for (int f : list) vertices.insert(vertices.end(), split[f].begin(), split[f].end());
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
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
  std::vector<Face> kept = drop_degenerate(positions, faces, welded, reporter);
  orient(kept, reporter);
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
