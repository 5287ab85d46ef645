#include "pipeline/half_subdivision.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "layout/layout_methods.h"
#include "pipeline/circle_domain.h"
#include "ricci/flow/presets.h"
#include "ricci/flow/ricci_flow.h"
#include "ricci/flow/scheme.h"
#include "ricci/mesh/errors.h"
#include "ricci/mesh/geometry.h"

namespace ricci::detail {

namespace {

std::complex<double> complex_of(const Eigen::Vector3d& p) {
  return {p.x(), p.y()};
}

// The sides of the pieces by vertex pair: the (one or two) pieces and the side's index in each.
struct PieceSides {
  struct Side {
    int piece[2] = {-1, -1};
    int corner[2] = {-1, -1};  // the side opposite this corner of the piece
    int count = 0;
  };
  std::unordered_map<uint64_t, Side> sides;

  static uint64_t key(int a, int b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
  }
  explicit PieceSides(const std::vector<std::array<int, 3>>& faces) {
    sides.reserve(2 * faces.size());
    for (size_t f = 0; f < faces.size(); ++f) {
      for (int c = 0; c < 3; ++c) {
        Side& s = sides[key(faces[f][(c + 1) % 3], faces[f][(c + 2) % 3])];
        if (s.count < 2) {
          s.piece[s.count] = static_cast<int>(f);
          s.corner[s.count] = c;
        }
        ++s.count;
      }
    }
  }
};

// Breadth-first order of the pieces from `start` across shared sides, with each piece's parent.
std::pair<std::vector<int>, std::vector<int>> sweep(const std::vector<std::array<int, 3>>& faces,
                                                    const PieceSides& sides, int start) {
  std::vector<int> order = {start}, parent(faces.size(), -2);
  parent[start] = -1;
  for (size_t head = 0; head < order.size(); ++head) {
    const int p = order[head];
    for (int c = 0; c < 3; ++c) {
      const PieceSides::Side& s =
          sides.sides.at(PieceSides::key(faces[p][(c + 1) % 3], faces[p][(c + 2) % 3]));
      if (s.count != 2) continue;
      const int q = s.piece[s.piece[0] == p ? 1 : 0];
      if (parent[q] != -2) continue;
      parent[q] = p;
      order.push_back(q);
    }
  }
  return {order, parent};
}

}  // namespace

HalfSubdivision half_subdivision(const CompactMesh& half, const CommonSubdivision& twice,
                                 const Triangulation& final_mesh, const Layout& frames) {
  const Geometry geometry = frames.geometry;
  const int n = half.num_vertices(), nf = half.num_faces();
  HalfSubdivision out;
  CommonSubdivision& sub = out.subdivision;
  sub.num_input_vertices = n;
  sub.num_flips = twice.num_flips;
  sub.seconds = twice.seconds;

  // The pieces in the half's faces, and the vertices they use: the half's, then new ones.
  std::vector<int> pieces;
  std::vector<int> index(twice.positions.size(), -1);
  for (int v = 0; v < n; ++v) index[v] = v;
  for (size_t f = 0; f < twice.faces.size(); ++f) {
    if (twice.input_face[f] >= nf) continue;
    pieces.push_back(static_cast<int>(f));
    for (int v : twice.faces[f]) {
      if (index[v] < 0) index[v] = -2;
    }
  }
  const int twice_n = twice.num_input_vertices;
  std::vector<int> vertices(n);
  for (int v = 0; v < n; ++v) vertices[v] = v;
  for (size_t v = twice_n; v < twice.positions.size(); ++v) {
    if (index[v] == -2) {
      index[v] = static_cast<int>(vertices.size());
      vertices.push_back(static_cast<int>(v));
    }
  }
  const int nv = static_cast<int>(vertices.size());
  sub.u.resize(nv);
  for (int i = 0; i < nv; ++i) {
    const int v = vertices[i];
    sub.positions.push_back(twice.positions[v]);
    sub.vertex_input_face.push_back(twice.vertex_input_face[v]);
    sub.vertex_barycentric.push_back(twice.vertex_barycentric[v]);
    sub.u[i] = twice.u[v];
    if (i >= n) {
      sub.vertex_input_edge.push_back(twice.vertex_input_edge[v - twice_n]);
      sub.vertex_edge_parameter.push_back(twice.vertex_edge_parameter[v - twice_n]);
    }
  }
  for (int f : pieces) {
    const auto& t = twice.faces[f];
    sub.faces.push_back({index[t[0]], index[t[1]], index[t[2]]});
    sub.input_face.push_back(twice.input_face[f]);
    sub.final_face.push_back(twice.final_face[f]);
  }
  for (int v = 0; v < n; ++v) {
    if (sub.vertex_input_face[v] >= nf) {
      throw LayoutError("doubled surface: vertex " + std::to_string(v) +
                        " is placed in a face of the mirror copy");
    }
  }

  // Development, breadth-first from a central piece (the middle of the longest of two sweeps, so
  // that in the Poincare disk no piece lies farther out than the surface's radius). Each piece is
  // placed by an isometry of its final face's frame (its own corners there are an isometric copy):
  // within a final face its parent's, across a side of the final triangulation the one that puts
  // that side's two ends where the parent's isometry puts them. Mapping a final side, not the
  // pieces' shared side, keeps directions as exact as the final triangle's: a sliver's short side
  // turned the pieces developed from it by its round-off over its length, which the long pieces
  // beyond it carried out to their far corners (dart-wam6.STL's disk: angle sums off by 7e-5).
  const int np = static_cast<int>(pieces.size());
  if (np == 0) throw LayoutError("doubled surface: no piece lies in the surface's faces");
  const PieceSides sides(sub.faces);
  int start = 0;
  if (geometry == Geometry::Hyperbolic) {
    const int far = sweep(sub.faces, sides, 0).first.back();
    const auto [order, parent] = sweep(sub.faces, sides, far);
    std::vector<int> path = {order.back()};
    while (parent[path.back()] >= 0) path.push_back(parent[path.back()]);
    start = path[path.size() / 2];
  }
  const std::pair<std::vector<int>, std::vector<int>> swept = sweep(sub.faces, sides, start);
  const std::vector<int>& order = swept.first;  // captured below: no structured binding (C++17)
  const std::vector<int>& parent = swept.second;
  if (static_cast<int>(order.size()) != np) {
    throw LayoutError("doubled surface: the pieces in the surface's faces are not connected");
  }
  // Poincare disk: as one chart, then, where that reaches beyond kOneChartRadius, in charts. The
  // first pass measures the reach and stops at distance 30 (a lower bound then): beyond about 37
  // |z| rounds to 1, and the isometries to NaN.
  std::vector<std::array<Eigen::Vector3d, 3>> placed(np);
  Layout& charts = out.charts;
  charts.geometry = geometry;
  const double last_rim = std::tanh(30.0 / 2);
  double far = 0;
  const auto develop = [&](bool in_charts) {
    std::vector<DiskIsometry> isometry(np, DiskIsometry{geometry, 1.0, 0.0});
    std::optional<ChartGrowth> growth;
    if (in_charts) {
      growth.emplace(charts, kChartRadius);
      charts.chart.assign(np, -1);
      charts.chart[start] = 0;
    }
    placed[start] = twice.corners[pieces[start]];
    for (size_t i = 1; i < order.size(); ++i) {
      const int q = order[i], p = parent[q];
      int qc = -1, pa = -1, pb = -1;  // q's corner off the shared side; p's corners on it
      for (int c = 0; c < 3; ++c) {
        bool shared = false;
        for (int d = 0; d < 3; ++d) shared = shared || sub.faces[p][d] == sub.faces[q][c];
        if (!shared) qc = c;
      }
      if (qc < 0) throw LayoutError("doubled surface: two pieces on the same three vertices");
      const int qa = (qc + 1) % 3, qb = (qc + 2) % 3;
      for (int d = 0; d < 3; ++d) {
        if (sub.faces[p][d] == sub.faces[q][qa]) pa = d;
        if (sub.faces[p][d] == sub.faces[q][qb]) pb = d;
      }
      if (pa < 0 || pb < 0) throw LayoutError("doubled surface: two pieces share no side");
      const auto& own = twice.corners[pieces[q]];
      // The candidates: the parent's isometry when both lie in one final face, and one per side
      // of q's final face across which the parent's final face lies (a side may be its own
      // face's, and two faces may share two sides); the one that puts the shared corners where
      // the parent has them, by far the nearest.
      const int fq = twice.final_face[pieces[q]], fp = twice.final_face[pieces[p]];
      const auto misfit = [&](const DiskIsometry& m) {
        return std::abs(m(complex_of(own[qa])) - complex_of(placed[p][pa])) +
               std::abs(m(complex_of(own[qb])) - complex_of(placed[p][pb]));
      };
      DiskIsometry best = isometry[p];
      double best_misfit = fq == fp ? misfit(best) : std::numeric_limits<double>::infinity();
      for (int c = 0; c < 3; ++c) {
        const int t = final_mesh.twin(3 * fq + c);
        if (t < 0 || t / 3 != fp) continue;
        // Halfedge 3 f + c runs from corner c + 1 to c + 2; its twin's ends are the other way.
        const int d = t % 3;
        const auto& mine = frames.corners[fq];
        const auto& theirs = frames.corners[fp];
        const DiskIsometry m = DiskIsometry::mapping(geometry, complex_of(mine[(c + 1) % 3]),
                                                     complex_of(mine[(c + 2) % 3]),
                                                     isometry[p](complex_of(theirs[(d + 2) % 3])),
                                                     isometry[p](complex_of(theirs[(d + 1) % 3])));
        const double e = misfit(m);
        if (e < best_misfit) best = m, best_misfit = e;
      }
      if (!(best_misfit < std::numeric_limits<double>::infinity())) {
        throw LayoutError("doubled surface: two pieces meet off their final faces' sides");
      }
      placed[q][qa] = placed[p][pa];
      placed[q][qb] = placed[p][pb];
      if (growth) {
        // Beyond the chart's rim: the isometry and the shared corners moved into another chart.
        const int k = charts.chart[p], j = growth->chart_for(k, best(complex_of(own[qc])));
        if (j != k) {
          const DiskIsometry& move = charts.chart_from_parent[static_cast<size_t>(j)];
          best = move * best;
          for (int c : {qa, qb}) {
            const std::complex<double> z = move(complex_of(placed[q][c]));
            placed[q][c] = Eigen::Vector3d(z.real(), z.imag(), 0);
          }
        }
        charts.chart[q] = j;
      }
      isometry[q] = best;
      const std::complex<double> z = best(complex_of(own[qc]));
      placed[q][qc] = Eigen::Vector3d(z.real(), z.imag(), 0);
      if (!in_charts) far = std::max(far, std::abs(z));
      if (!in_charts && geometry == Geometry::Hyperbolic && std::abs(z) > last_rim) return;
    }
  };
  develop(false);
  if (geometry == Geometry::Hyperbolic) {
    for (const auto& z : placed[start]) far = std::max(far, z.norm());
    charts.reach = 2 * std::atanh(std::min(far, 1 - 1e-16));
    if (charts.reach > kOneChartRadius) develop(true);
  }
  sub.chart = charts.chart;

  // Plane: per vertex the mean of its corners, whose spread is the closure error. Poincare disk:
  // the surface is cut open where the development did not cross, so positions are per corner
  // (vertex_layout: the first corner's).
  std::vector<Eigen::Vector3d> sum(nv, Eigen::Vector3d::Zero());
  std::vector<int> count(nv, 0);
  for (int p = 0; p < np; ++p) {
    for (int c = 0; c < 3; ++c) {
      const int v = sub.faces[p][c];
      if (geometry == Geometry::Euclidean || count[v] == 0) sum[v] += placed[p][c], ++count[v];
    }
  }
  sub.vertex_layout.resize(nv);
  for (int v = 0; v < nv; ++v) {
    if (count[v] == 0) throw LayoutError("doubled surface: a vertex lies in no piece");
    sub.vertex_layout[v] = sum[v] / count[v];
  }
  if (geometry != Geometry::Euclidean) {
    sub.corners = std::move(placed);
    out.closure_error = std::nan("");
    return out;
  }
  sub.corners.resize(np);
  for (int p = 0; p < np; ++p) {
    for (int c = 0; c < 3; ++c) {
      sub.corners[p][c] = sub.vertex_layout[sub.faces[p][c]];
      out.closure_error = std::max(out.closure_error, (placed[p][c] - sub.corners[p][c]).norm());
    }
  }
  out.piece_corners = std::move(placed);

  // The boundary: sides of one piece only, each on one boundary edge of the half (the one its new
  // vertex lies on, or the one joining its two ends), measured in the piece's own frame.
  out.boundary_lengths.assign(half.num_edges(), 0.0);
  std::unordered_map<uint64_t, int> boundary_edge;
  for (int e = 0; e < half.num_edges(); ++e) {
    if (half.is_boundary_edge(e)) {
      const auto [a, b] = half.edge_vertices(e);
      boundary_edge[PieceSides::key(a, b)] = e;
    }
  }
  for (const auto& [key, s] : sides.sides) {
    if (s.count != 1) continue;
    const int p = s.piece[0], c = s.corner[0];
    const int a = sub.faces[p][(c + 1) % 3], b = sub.faces[p][(c + 2) % 3];
    int e = -1;
    for (int v : {a, b}) {
      if (v >= n) e = sub.vertex_input_edge[v - n];
    }
    if (e < 0) {
      const auto it = boundary_edge.find(key);
      if (it != boundary_edge.end()) e = it->second;
    }
    if (e < 0 || !half.is_boundary_edge(e)) {
      throw LayoutError("doubled surface: a side of the pieces' boundary lies on no boundary edge");
    }
    const auto& own = twice.corners[pieces[p]];
    out.boundary_lengths[e] += (own[(c + 1) % 3] - own[(c + 2) % 3]).norm();
  }
  return out;
}

}  // namespace ricci::detail
