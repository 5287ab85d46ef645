// The repairs that come before the split into fans and components (repair_steps.h).
#include "repair/repair_steps.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "mesh/mesh_checks.h"
#include "ricci/mesh/errors.h"

namespace ricci::detail {

void Reporter::add(const std::string& what, const std::string& element, int index) {
  auto it = std::find_if(report.entries.begin(), report.entries.end(),
                         [&](const RepairReport::Entry& e) { return e.what == what; });
  if (it == report.entries.end()) {
    report.entries.push_back({what, element, 0, {}});
    it = report.entries.end() - 1;
  }
  ++it->count;
  if (it->first.size() < 3) it->first.push_back(index);
}

void Reporter::merge(const Reporter& other) {
  for (const RepairReport::Entry& e : other.report.entries) {
    for (int index : e.first) add(e.what, e.element, index);
    auto it = std::find_if(report.entries.begin(), report.entries.end(),
                           [&](const RepairReport::Entry& x) { return x.what == e.what; });
    it->count += e.count - static_cast<int>(e.first.size());
  }
}

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return lo << 32 | hi;
}

EdgeMap::EdgeMap(const std::vector<Face>& faces) {
  const int n = 3 * static_cast<int>(faces.size());
  int num_vertices = 0;
  for (const Face& f : faces) {
    for (int v : f.v) num_vertices = std::max(num_vertices, v + 1);
  }
  const auto ends = [&](int use) {
    const auto& v = faces[use / 3].v;
    return std::array<int, 2>{v[use % 3], v[(use % 3 + 1) % 3]};
  };
  const std::vector<int> order = order_by_vertex_pair(num_vertices, n, ends);
  keys_.resize(n);
  uses_.resize(n);
  edge_of_use_.resize(n);
  for (int i = 0; i < n; ++i) {
    const int use = order[i], f = use / 3, c = use % 3;
    keys_[i] = edge_key(faces[f].v[c], faces[f].v[(c + 1) % 3]);
    uses_[i] = {f, faces[f].v[c]};
    if (i == 0 || keys_[i] != keys_[i - 1]) start_.push_back(i);
    edge_of_use_[use] = start_.size() - 1;
  }
  start_.push_back(n);
}

std::vector<std::pair<EdgeUse, EdgeUse>> glued_pairs(const EdgeUses& uses) {
  // Each use, in face order, pairs with the earliest use still waiting that traverses the edge the
  // other way; the uses waiting all traverse it one way, so they queue. Linear in the uses (a
  // search for each partner took 14.5 s for 200k faces on one edge); the pairs in the order of
  // their first use, as the search gave them.
  std::vector<std::pair<size_t, size_t>> pairs;
  std::vector<size_t> waiting;
  size_t front = 0;
  for (size_t j = 0; j < uses.size(); ++j) {
    if (front < waiting.size() && uses[waiting[front]].from != uses[j].from) {
      pairs.emplace_back(waiting[front++], j);
    } else {
      waiting.push_back(j);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<std::pair<EdgeUse, EdgeUse>> out;
  out.reserve(pairs.size());
  for (const auto& [i, j] : pairs) out.emplace_back(uses[i], uses[j]);
  return out;
}

// === Needles, repeated vertices, duplicates

std::vector<Face> drop_degenerate(const std::vector<Eigen::Vector3d>& p,
                                  const std::vector<std::array<int, 3>>& input,
                                  std::vector<int>& represented_by, Reporter& reporter, bool join) {
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
  if (join) {
    // Two edges of faces whose ends are at the same two positions (compared as numbers: -0 and +0
    // alike, as the STL reader keys its corners) are one edge: their ends are joined. Vertices
    // that meet at a point only stay apart (joined, they would be split again into a copy per
    // fan). The faces' vertices get one id per position (a sort of the vertices); only where two
    // share one are the edges ordered by their ids' pair (linear, order_by_vertex_pair).
    std::vector<int> used;
    std::vector<char> seen(n, 0);
    for (const auto& t : input) {
      for (int v : t) {
        if (!seen[v]) seen[v] = 1, used.push_back(v);
      }
    }
    const auto less = [&](int a, int b) {
      const Eigen::Vector3d &x = p[a], &y = p[b];
      if (x.x() != y.x()) return x.x() < y.x();
      if (x.y() != y.y()) return x.y() < y.y();
      return x.z() < y.z();
    };
    std::sort(used.begin(), used.end(), less);
    std::vector<int> position(n, -1);
    int positions = 0;
    for (size_t i = 0; i < used.size(); ++i) {
      if (i > 0 && less(used[i - 1], used[i])) ++positions;
      position[used[i]] = positions;
    }
    if (!used.empty() && positions + 1 < static_cast<int>(used.size())) {
      const int uses = 3 * static_cast<int>(input.size());
      const auto ends = [&](int use) {
        const auto& t = input[use / 3];
        return std::array<int, 2>{position[t[use % 3]], position[t[(use % 3 + 1) % 3]]};
      };
      const std::vector<int> order = order_by_vertex_pair(positions + 1, uses, ends);
      // The vertex of `use`'s edge at the lower position id, then the other.
      const auto ordered = [&](int use) {
        const auto& t = input[use / 3];
        const int a = t[use % 3], b = t[(use % 3 + 1) % 3];
        return position[a] <= position[b] ? std::array<int, 2>{a, b} : std::array<int, 2>{b, a};
      };
      for (size_t i = 1; i < order.size(); ++i) {
        const auto x = ends(order[i - 1]), y = ends(order[i]);
        if (x[0] == x[1] || std::minmax(x[0], x[1]) != std::minmax(y[0], y[1])) continue;
        const auto xa = ordered(order[i - 1]), ya = ordered(order[i]);
        for (int k = 0; k < 2; ++k) {
          if (weld.find(xa[k]) != weld.find(ya[k])) {
            reporter.add(kJoinedVertices, "vertex", std::max(xa[k], ya[k]));
            weld.unite(xa[k], ya[k]);
          }
        }
      }
    }
  }
  std::vector<int> smallest(n, n);
  for (int v = 0; v < n; ++v) smallest[weld.find(v)] = std::min(smallest[weld.find(v)], v);
  represented_by.resize(n);
  for (int v = 0; v < n; ++v) represented_by[v] = smallest[weld.find(v)];
  const auto welded_face = [&](int f) -> std::array<int, 3> {
    return {represented_by[input[f][0]], represented_by[input[f][1]], represented_by[input[f][2]]};
  };
  const auto repeats_a_vertex = [&](int f) {
    const std::array<int, 3> v = welded_face(f);
    return v[0] == v[1] || v[1] == v[2] || v[2] == v[0];
  };
  // Faces with three distinct vertices; a later one on the same three is a duplicate.
  std::vector<int> proper;
  for (int f = 0; f < static_cast<int>(input.size()); ++f) {
    if (!repeats_a_vertex(f)) proper.push_back(f);
  }
  std::vector<char> duplicate(input.size(), 0);
  for (int k : repeated_triangles(n, static_cast<int>(proper.size()),
                                  [&](int k) { return welded_face(proper[k]); })) {
    duplicate[proper[k]] = 1;
  }
  std::vector<Face> faces;
  for (int f = 0; f < static_cast<int>(input.size()); ++f) {
    if (repeats_a_vertex(f)) {
      reporter.add("faces with a repeated vertex dropped", "face", f);
    } else if (duplicate[f]) {
      reporter.add("duplicate faces dropped", "face", f);
    } else {
      faces.push_back({welded_face(f), f});
    }
  }
  return faces;
}

// === Orientation

void orient(std::vector<Face>& faces, Reporter& reporter) {
  const int nf = static_cast<int>(faces.size());
  const EdgeMap edges(faces);
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
        const EdgeUses uses = edges.uses(edges.edge_of(f, c));
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

namespace {

// The corner of a zero-area face whose vertex lies inside the opposite (longest) edge, or -1.
int cap_corner(const std::vector<Eigen::Vector3d>& p, const Face& f) {
  const Eigen::Vector3d& a = p[f.v[0]];
  const Eigen::Vector3d e1 = p[f.v[1]] - a, e2 = p[f.v[2]] - a;
  const std::array<double, 3> opposite = {(p[f.v[2]] - p[f.v[1]]).squaredNorm(), e2.squaredNorm(),
                                          e1.squaredNorm()};
  const int c =
      static_cast<int>(std::max_element(opposite.begin(), opposite.end()) - opposite.begin());
  // The same test as CompactMesh's: twice the area against the longest edge squared; or side
  // lengths that make no triangle in double precision (the metric the flow starts from).
  const double longest = std::sqrt(opposite[c]);
  const double others = std::sqrt(opposite[(c + 1) % 3]) + std::sqrt(opposite[(c + 2) % 3]);
  return e1.cross(e2).norm() > 1e-12 * opposite[c] && others > longest * (1 + 1e-14) ? -1 : c;
}

}  // namespace

void remove_caps(const std::vector<Eigen::Vector3d>& p, std::vector<Face>& faces,
                 Reporter& reporter) {
  // Per face, whether it is a cap: found again only for the faces a pass changes or adds.
  std::vector<char> cap(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) cap[f] = cap_corner(p, faces[f]) >= 0;
  std::ptrdiff_t caps = std::count(cap.begin(), cap.end(), 1);
  // A pass splits each cap's neighbour; a fan of caps around one vertex (a collapsed polygon, its
  // vertices on one line) can lose one a pass, or none for a dozen passes and then many (a
  // chair's cushion of Sweet Home 3D's furniture: 40 caps in 38 passes; a polygon of 121 sides
  // collapsed onto a line, as repair_test.cpp's collapsed_fan(60): 110 caps left for 12 passes,
  // none 33 passes later). The passes go on while the caps left reach a new low within kStalled
  // passes (at least the 20 passes made before), at most kMostPasses (each costs a scan of the
  // faces: 10 s in all with a 1M-face grid beside such a polygon of 2,401 sides).
  constexpr int kStalled = 32, kMostPasses = 1000;
  std::ptrdiff_t fewest = caps;
  std::vector<int> removed;  // the input faces of the caps removed, in order
  std::vector<char> at_cap(p.size(), 0);
  std::vector<int> local(faces.size(), -1);
  for (int pass = 0, since_fewer = 0; caps > 0 && pass < kMostPasses && since_fewer < kStalled;
       ++pass) {
    // The faces with two vertices or more among the caps': every face on a cap's edge is one, so
    // their edge map has each cap's edges with all their faces (a map of every face each pass
    // took the repair of the 1M-face grid beside the 2,401-gon above to 127 s).
    for (size_t f = 0; f < faces.size(); ++f) {
      if (cap[f]) {
        for (int v : faces[f].v) at_cap[v] = 1;
      }
    }
    std::vector<int> near;
    std::vector<Face> near_faces;
    for (size_t f = 0; f < faces.size(); ++f) {
      const auto& v = faces[f].v;
      if (at_cap[v[0]] + at_cap[v[1]] + at_cap[v[2]] >= 2) {
        local[f] = static_cast<int>(near.size());
        near.push_back(static_cast<int>(f));
        near_faces.push_back(faces[f]);
      }
    }
    for (size_t f = 0; f < faces.size(); ++f) {
      if (cap[f]) {
        for (int v : faces[f].v) at_cap[v] = 0;
      }
    }
    const EdgeMap edges(near_faces);
    std::vector<char> touched(faces.size(), 0), dropped(faces.size(), 0), changed(faces.size(), 0);
    std::vector<Face> added;
    for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
      if (!cap[f] || touched[f]) continue;
      const int c = cap_corner(p, faces[f]);
      const int m = faces[f].v[c], a = faces[f].v[(c + 1) % 3], b = faces[f].v[(c + 2) % 3];
      const EdgeUses uses = edges.uses(edges.edge_of(local[f], (c + 1) % 3));
      const EdgeUse* across = nullptr;
      for (const EdgeUse& u : uses) {
        if (near[u.face] != f) across = &u;
      }
      const bool glued = uses.size() == 2 && across != nullptr;
      const int other = glued ? near[across->face] : -1;
      if (glued && touched[other]) continue;  // next pass
      touched[f] = dropped[f] = 1;
      removed.push_back(faces[f].input);
      if (!glued || across->from != b) continue;  // boundary (or non-manifold): dropped
      Face& g = faces[other];
      touched[other] = changed[other] = 1;
      int d = -1;
      for (int v : g.v) {
        if (v != a && v != b) d = v;
      }
      // The face across is the cap itself, reversed (its vertex off a-b is m): the two are a
      // zero-area fold, and splitting one at m would make faces that repeat m. Both go.
      if (d < 0 || d == m) {
        dropped[other] = 1;
        removed.push_back(g.input);
        continue;
      }
      added.push_back({{m, a, d}, g.input});  // g runs b -> a -> d; m lies on b -> a
      g.v = {b, m, d};
    }
    for (int f : near) local[f] = -1;
    std::vector<Face> kept;
    std::vector<char> kept_cap;
    for (size_t f = 0; f < faces.size(); ++f) {
      if (dropped[f]) continue;
      kept.push_back(faces[f]);
      kept_cap.push_back(changed[f] ? cap_corner(p, faces[f]) >= 0 : cap[f]);
    }
    for (const Face& f : added) {
      kept.push_back(f);
      kept_cap.push_back(cap_corner(p, f) >= 0);
    }
    faces = std::move(kept);
    cap = std::move(kept_cap);
    local.resize(faces.size(), -1);
    caps = std::count(cap.begin(), cap.end(), 1);
    since_fewer = caps < fewest ? 0 : since_fewer + 1;
    fewest = std::min(fewest, caps);
  }
  // Each input face once (the pieces of a split cap keep its index).
  const auto report_once = [&](const std::vector<int>& inputs, const std::string& what) {
    std::vector<int> sorted = inputs;
    std::sort(sorted.begin(), sorted.end());
    std::vector<char> said(sorted.size(), 0);
    for (int input : inputs) {
      const size_t at = std::lower_bound(sorted.begin(), sorted.end(), input) - sorted.begin();
      if (!said[at]) reporter.add(what, "face", input);
      said[at] = 1;
    }
  };
  report_once(removed, "zero-area faces removed (the face across the longest edge split)");
  // Caps among four or more vertices on one line can split one another in turn without end (a
  // radiator's fins: three caps left after every other pass); those the passes leave are
  // dropped (a closed surface opens there), and the faces the splits made twice on the same three
  // vertices, as duplicate input faces are.
  std::vector<Face> kept;
  std::vector<int> left, twice;
  for (size_t f = 0; f < faces.size(); ++f) {
    if (cap[f]) {
      left.push_back(faces[f].input);
    } else {
      kept.push_back(faces[f]);
    }
  }
  report_once(left, "zero-area faces dropped (left by the splits)");
  std::vector<char> duplicate(kept.size(), 0);
  for (int k : repeated_triangles(static_cast<int>(p.size()), static_cast<int>(kept.size()),
                                  [&](int k) { return kept[k].v; })) {
    duplicate[k] = 1;
    twice.push_back(kept[k].input);
  }
  report_once(twice, "faces the splits made twice dropped");
  faces.clear();
  for (size_t k = 0; k < kept.size(); ++k) {
    if (!duplicate[k]) faces.push_back(kept[k]);
  }
}

}  // namespace ricci::detail
