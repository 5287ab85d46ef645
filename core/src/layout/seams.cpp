#include "ricci/layout/seams.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <utility>

#include "layout/cut_graph.h"
#include "mesh/mesh_checks.h"

namespace ricci {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Shortest paths over the allowed edges from a set of sources.
struct ShortestPaths {
  std::vector<double> distance;
  std::vector<int> via;     // per vertex: the edge it was reached by (-1 at a source)
  std::vector<int> source;  // per vertex: the source its path starts from
};

class EdgeGraph {
 public:
  EdgeGraph(const Triangulation& mesh, const std::vector<double>& lengths,
            const std::vector<char>& allowed)
      : mesh_(mesh), lengths_(lengths), adjacent_(mesh.num_vertices()) {
    for (int e = 0; e < mesh.num_edges(); ++e) {
      if (!allowed.empty() && !allowed[e]) continue;
      const auto [a, b] = mesh.edge_vertices(e);
      adjacent_[a].push_back(e), adjacent_[b].push_back(e);
    }
  }

  int other(int e, int v) const {
    const auto [a, b] = mesh_.edge_vertices(e);
    return a == v ? b : a;
  }
  const std::vector<int>& edges_at(int v) const { return adjacent_[v]; }
  double length(int e) const { return lengths_[e]; }

  // Dijkstra from `sources`, not across edges where `blocked` is set, and not on from vertices
  // where `stop` is set (they are reached, not passed; either mask may be empty). With `until`,
  // the search ends at the first vertex it settles for which until(v) holds (the nearest such),
  // whose index it returns in `found` (-1: none).
  ShortestPaths from(const std::vector<int>& sources, const std::vector<char>& blocked = {},
                     const std::vector<char>& stop = {}, const std::function<bool(int)>& until = {},
                     int* found = nullptr) const {
    const int nv = mesh_.num_vertices();
    ShortestPaths p{std::vector<double>(nv, kInfinity), std::vector<int>(nv, -1),
                    std::vector<int>(nv, -1)};
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    for (int s : sources) {
      p.distance[s] = 0, p.source[s] = s;
      queue.push({0, s});
    }
    while (!queue.empty()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > p.distance[v]) continue;
      if (until && until(v)) {
        *found = v;
        return p;
      }
      if (!stop.empty() && stop[v] && p.source[v] != v) continue;
      for (int e : adjacent_[v]) {
        if (!blocked.empty() && blocked[e]) continue;
        const int w = other(e, v);
        const double via = d + lengths_[e];
        if (via < p.distance[w]) {
          p.distance[w] = via, p.via[w] = e, p.source[w] = p.source[v];
          queue.push({via, w});
        }
      }
    }
    return p;
  }

  // Marks the tree path from v back to its source.
  void mark_path(const ShortestPaths& p, int v, std::vector<char>& cut) const {
    while (p.via[v] >= 0) {
      cut[p.via[v]] = 1;
      v = other(p.via[v], v);
    }
  }

 private:
  const Triangulation& mesh_;
  const std::vector<double>& lengths_;
  std::vector<std::vector<int>> adjacent_;
};

// A vertex central in the metric: least max distance to the two ends of a double sweep.
int central_vertex(const EdgeGraph& graph, int num_vertices) {
  const auto farthest = [](const std::vector<double>& d) {
    int best = 0;
    for (int v = 0; v < static_cast<int>(d.size()); ++v) {
      if (d[v] < kInfinity && d[v] > d[best]) best = v;
    }
    return best;
  };
  const int a = farthest(graph.from({0}).distance);
  const std::vector<double> from_a = graph.from({a}).distance;
  const std::vector<double> from_b = graph.from({farthest(from_a)}).distance;
  int root = 0;
  for (int v = 0; v < num_vertices; ++v) {
    if (std::max(from_a[v], from_b[v]) < std::max(from_a[root], from_b[root])) root = v;
  }
  return root;
}

// The 2g loops of the greedy homology basis, marked in `cut`, on the surface with each boundary
// loop contracted to one node: closed, of the same genus, where running along a boundary costs
// nothing (the boundary is open already). A loop through such a node is cut as arcs that end on
// that boundary loop. (With the boundary loops capped by disks instead, a loop could run along a
// cap's rim in two places; dropping its boundary edges then left two arcs with both ends on one
// boundary loop, which cut a region off: dart-wam6.STL's half made 7 charts.)
void mark_homology_loops(const Triangulation& mesh, const std::vector<double>& lengths,
                         const std::vector<char>& allowed, std::vector<char>& cut) {
  if (mesh.genus() == 0) return;
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  std::vector<int> node(nv);
  std::iota(node.begin(), node.end(), 0);
  for (const std::vector<int>& loop : mesh.boundary_loops()) {
    for (int v : loop) node[v] = loop.front();
  }
  // The contracted surface's edges: the allowed inner edges (a boundary edge contracts to a
  // point). An inner edge with both ends on one boundary loop is a loop at its node.
  std::vector<char> contracted(mesh.num_edges(), 0);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    contracted[e] = !mesh.is_boundary_edge(e) && (allowed.empty() || allowed[e]);
  }
  std::vector<double> contracted_lengths(mesh.num_edges(), 0.0);
  std::vector<char> walked(mesh.num_edges(), 0);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (contracted[e]) contracted_lengths[e] = lengths[e];
    walked[e] = contracted[e] || mesh.is_boundary_edge(e);
  }
  // Shortest paths from a central vertex, every boundary loop's vertices at one distance: the
  // boundary edges cost nothing.
  const EdgeGraph graph(mesh, contracted_lengths, walked);
  const ShortestPaths tree = graph.from({node[central_vertex(graph, nv)]});
  // The tree's edges as the contracted surface's: each node's edge in is an inner edge by which
  // the search reached one of its vertices from strictly nearer the root, the representative's
  // own first (a vertex reached along its boundary loop is its node; an edge from no nearer, where
  // lengths of zero tie, could close a cycle).
  const auto edge_in = [&](int v) {
    const int e = tree.via[v];
    if (e < 0 || !contracted[e]) return -1;
    const auto [a, b] = mesh.edge_vertices(e);
    const int from = a == v ? b : a;
    return node[from] != node[v] && tree.distance[from] < tree.distance[v] ? e : -1;
  };
  std::vector<int> via(nv, -1);
  for (int v = 0; v < nv; ++v) {
    if (node[v] == v) via[v] = edge_in(v);
  }
  for (int v = 0; v < nv; ++v) {
    if (node[v] != v && via[node[v]] < 0) via[node[v]] = edge_in(v);
  }
  std::vector<char> in_tree(mesh.num_edges(), 0);
  for (int v = 0; v < nv; ++v) {
    if (node[v] == v && via[v] >= 0) in_tree[via[v]] = 1;
  }
  const auto mark_path = [&](int v) {
    for (int n = node[v]; via[n] >= 0;) {
      const int e = via[n];
      cut[e] = 1;
      const auto [a, b] = mesh.edge_vertices(e);
      n = node[a] == n ? node[b] : node[a];
    }
  };
  // The dual tree over the faces takes the edges not allowed first (no seam may run there), then
  // the others by decreasing loop length, so the edges left close the shortest loops.
  std::vector<int> order;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (!in_tree[e] && !mesh.is_boundary_edge(e)) order.push_back(e);
  }
  const auto loop_length = [&](int e) {
    if (!contracted[e]) return kInfinity;
    const auto [a, b] = mesh.edge_vertices(e);
    return tree.distance[a] + tree.distance[b] + lengths[e];
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return loop_length(a) > loop_length(b); });
  detail::UnionFind dual(nf);
  for (int e : order) {
    const auto [f, g] = mesh.edge_faces(e);
    if (dual.find(f) != dual.find(g)) {
      dual.unite(f, g);
      continue;
    }
    const auto [a, b] = mesh.edge_vertices(e);
    cut[e] = 1;
    mark_path(a);
    mark_path(b);
  }
}

// The cut so far, the boundary loops and the cones joined by a Steiner tree of shortest paths.
void join_terminals(const Triangulation& mesh, const EdgeGraph& graph,
                    const std::vector<int>& cones, std::vector<char>& cut) {
  const int nv = mesh.num_vertices();
  // Terminal groups: connected pieces of the cut and boundary, and each cone.
  detail::UnionFind pieces(nv);
  std::vector<char> terminal(nv, 0);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (!cut[e] && !mesh.is_boundary_edge(e)) continue;
    const auto [a, b] = mesh.edge_vertices(e);
    pieces.unite(a, b);
    terminal[a] = terminal[b] = 1;
  }
  for (int c : cones) terminal[c] = 1;
  std::vector<int> sources;
  for (int v = 0; v < nv; ++v) {
    if (terminal[v]) sources.push_back(v);
  }
  if (sources.empty()) return;
  const ShortestPaths regions = graph.from(sources);
  struct Bridge {
    double cost;
    int edge;
  };
  std::vector<Bridge> bridges;
  for (int v = 0; v < nv; ++v) {
    for (int e : graph.edges_at(v)) {
      const int w = graph.other(e, v);
      if (w < v || regions.source[v] < 0 || regions.source[w] < 0) continue;
      if (pieces.find(regions.source[v]) == pieces.find(regions.source[w])) continue;
      bridges.push_back({regions.distance[v] + graph.length(e) + regions.distance[w], e});
    }
  }
  std::stable_sort(bridges.begin(), bridges.end(),
                   [](const Bridge& a, const Bridge& b) { return a.cost < b.cost; });
  for (const Bridge& b : bridges) {
    const auto [v, w] = mesh.edge_vertices(b.edge);
    const int sv = pieces.find(regions.source[v]), sw = pieces.find(regions.source[w]);
    if (sv == sw) continue;
    pieces.unite(sv, sw);
    cut[b.edge] = !mesh.is_boundary_edge(b.edge);
    graph.mark_path(regions, v, cut);
    graph.mark_path(regions, w, cut);
  }
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (mesh.is_boundary_edge(e)) cut[e] = 0;
  }
}

// Cut and boundary edges at each vertex.
std::vector<int> cut_degree(const Triangulation& mesh, const std::vector<char>& cut) {
  std::vector<int> degree(mesh.num_vertices(), 0);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (!cut[e] && !mesh.is_boundary_edge(e)) continue;
    for (int v : mesh.edge_vertices(e)) ++degree[v];
  }
  return degree;
}

// The edges at an interior vertex in their turn around it from halfedge `first` into it, each with
// its angle from the first (the sum of the vertex's corner angles between them), and its whole
// angle.
struct Spokes {
  std::vector<int> edge;
  std::vector<double> at;
  double angle = 0;
};

Spokes spokes_around(const Triangulation& mesh, int first,
                     const std::vector<double>& corner_angles) {
  Spokes s;
  // Halfedge 3 f + k runs from corner k + 1 to corner k + 2: into c at corner k + 2; the next face
  // around c is across f's side from c, whose twin comes into c.
  for (int h = first;;) {
    const int f = h / 3, k = h % 3, at_c = (k + 2) % 3;
    s.edge.push_back(mesh.face_edge(f, k));
    s.at.push_back(s.angle);
    s.angle += corner_angles[3 * f + at_c];
    const int out = 3 * f + (k + 1) % 3;  // from c to corner k: f's other side at c
    const int across = mesh.twin(out);
    if (across < 0) return {};  // c on the boundary
    h = across;
    if (h == first) break;
  }
  return s;
}

// Cone c gets another branch: the shortest path, off the cut, to a vertex of the cut or the
// boundary that is neither c, nor a cut neighbour of c, nor nearer to c along the cut than
// `away` (3D length), leaving c by an edge of `leave` (empty: any). False where none is reached.
bool add_branch(const Triangulation& mesh, const EdgeGraph& graph, int c, double away,
                std::vector<char>& cut, const std::vector<int>& leave = {}) {
  const std::vector<int> degree = cut_degree(mesh, cut);
  std::vector<char> near(mesh.num_vertices(), 0);
  near[c] = 1;
  for (int e : graph.edges_at(c)) {
    if (cut[e]) near[graph.other(e, c)] = 1;
  }
  if (away > 0) {  // along the cut, to `away` from c
    std::vector<char> off_cut(cut.size());
    for (size_t e = 0; e < cut.size(); ++e) off_cut[e] = !cut[e];
    const ShortestPaths along = graph.from({c}, off_cut);
    for (int v = 0; v < mesh.num_vertices(); ++v) near[v] = near[v] || along.distance[v] < away;
  }
  std::vector<char> on_cut(mesh.num_vertices(), 0);
  for (int v = 0; v < mesh.num_vertices(); ++v) on_cut[v] = degree[v] > 0;
  std::vector<char> blocked = cut;
  if (!leave.empty()) {
    for (int e : graph.edges_at(c)) blocked[e] = 1;
    for (int e : leave) blocked[e] = cut[e];
  }
  // The path ends at the first cut vertex it meets: it never runs along the cut or the boundary.
  // The search stops at the nearest vertex of the cut that may end it.
  int end = -1;
  const ShortestPaths p = graph.from(
      {c}, blocked, on_cut, [&](int v) { return degree[v] > 0 && !near[v]; }, &end);
  if (end < 0) return false;
  graph.mark_path(p, end, cut);
  return true;
}

// Cone c's widest wedge (between cut edges that follow each other around it), while it is wider
// than `widest`, gets a branch that leaves c where both parts are within `widest` if the wedge is
// at most twice that, else within its middle half (the shortest such path; with no edge there, by
// the edge nearest the middle). The branch ends on the cut at least `away` from c along it, or,
// where no such vertex is reached, anywhere but at c's cut neighbours. Where the wedge has no
// edge to leave by, or no branch from it reaches the cut, the cone keeps its wedges (the charts'
// overlap splits part what overlaps).
void narrow_wedges(const Triangulation& mesh, const EdgeGraph& graph, int into_c,
                   const std::vector<double>& corner_angles, double widest, double away,
                   std::vector<char>& cut) {
  const int c = mesh.halfedge_head(into_c);
  const Spokes s = spokes_around(mesh, into_c, corner_angles);
  if (!(s.angle > widest)) return;
  const int n = static_cast<int>(s.edge.size());
  std::vector<char> usable(n, 0);
  for (int i = 0; i < n; ++i) {
    const auto& at_c = graph.edges_at(c);
    usable[i] = std::find(at_c.begin(), at_c.end(), s.edge[i]) != at_c.end();
  }
  for (int round = 0; round < n; ++round) {
    std::vector<int> cuts;
    for (int i = 0; i < n; ++i) {
      if (cut[s.edge[i]]) cuts.push_back(i);
    }
    if (cuts.empty()) return;
    // The widest wedge: from cut spoke `from`, `width` around.
    int from = -1;
    double width = -1;
    for (size_t j = 0; j < cuts.size(); ++j) {
      const int a = cuts[j], b = cuts[(j + 1) % cuts.size()];
      const double w = b > a ? s.at[b] - s.at[a] : s.angle - s.at[a] + s.at[b];
      if (w > width) from = a, width = w;
    }
    if (!(width > widest)) return;
    // Where one branch can leave both parts within `widest`, where it does; else the middle half.
    const double low = width <= 2 * widest ? width - widest : width / 4;
    const double high = width <= 2 * widest ? widest : 3 * width / 4;
    std::vector<int> middle;
    int nearest = -1;
    double nearest_off = kInfinity;
    for (int step = 1; step < n; ++step) {
      const int i = (from + step) % n;
      if (cut[s.edge[i]]) break;
      if (!usable[i]) continue;
      const double t = i > from ? s.at[i] - s.at[from] : s.angle - s.at[from] + s.at[i];
      if (t >= low && t <= high) middle.push_back(s.edge[i]);
      if (std::abs(t - width / 2) < nearest_off) nearest = i, nearest_off = std::abs(t - width / 2);
    }
    if (nearest < 0) return;  // no edge inside the wedge to leave by
    if (middle.empty()) middle.push_back(s.edge[nearest]);
    if (!add_branch(mesh, graph, c, away, cut, middle) &&
        !add_branch(mesh, graph, c, 0, cut, middle)) {
      return;
    }
  }
}

}  // namespace

CutGraph cut_through_cones(const Triangulation& mesh, const std::vector<double>& lengths,
                           const std::vector<int>& cones, const ConeWedges& wedges,
                           const std::vector<char>& allowed) {
  CutGraph g;
  g.num_generators = 2 * mesh.genus() + std::max(0, mesh.num_boundary_loops() - 1);
  g.cut.assign(mesh.num_edges(), 0);
  if (mesh.num_faces() == 0) return g;
  const EdgeGraph graph(mesh, lengths, allowed);
  mark_homology_loops(mesh, lengths, allowed, g.cut);
  join_terminals(mesh, graph, cones, g.cut);
  std::vector<char> is_cone(mesh.num_vertices(), 0);
  for (int c : cones) is_cone[c] = 1;
  detail::prune_cut(mesh, g.cut, is_cone);
  if (!wedges.corner_angles.empty() && !cones.empty()) {
    std::vector<int> into(mesh.num_vertices(), -1);  // at each cone, a halfedge into it
    for (int c : cones) into[c] = -2;
    for (int h = 0; h < mesh.num_halfedges(); ++h) {
      if (into[mesh.halfedge_head(h)] == -2) into[mesh.halfedge_head(h)] = h;
    }
    for (int c : cones) {
      if (into[c] >= 0)
        narrow_wedges(mesh, graph, into[c], wedges.corner_angles, wedges.widest, wedges.branch_end,
                      g.cut);
    }
  }
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (mesh.is_boundary_edge(e)) g.cut[e] = 0;
  }
  const std::vector<int> degree = detail::prune_cut(mesh, g.cut, is_cone);
  g.paths = detail::split_cut_into_paths(mesh, g.cut, degree, is_cone);
  return g;
}

void connect_cut(const Triangulation& mesh, const std::vector<double>& lengths,
                 std::vector<char>& cut, const std::vector<char>& allowed) {
  if (mesh.num_faces() == 0) return;
  join_terminals(mesh, EdgeGraph(mesh, lengths, allowed), {}, cut);
}

double cut_length(const Triangulation& mesh, const CutGraph& cut,
                  const std::vector<double>& lengths) {
  double total = 0;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (cut.cut[e]) total += lengths[e];
  }
  return total;
}

}  // namespace ricci
