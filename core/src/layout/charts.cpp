#include "ricci/layout/charts.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include "layout/corners.h"
#include "mesh/mesh_checks.h"
#include "mesh/plane.h"
#include "ricci/mesh/geometry.h"

namespace ricci {

namespace {

using detail::cross;

// A side placed by a neighbour at more than this times its own length, or less than its inverse,
// differs by more than rounding: the pieces of a needle whose crossings the common subdivision
// placed apart (a robot arm's part, 17,939 flips: a piece's side 1.4e-5 long in its own drawing,
// 5.8e-4 in its neighbour's).
constexpr double kPlacedMismatch = 2;

// The corner opposite p-q of a triangle with sides a (opposite p), b (opposite q) and c (p-q),
// counter-clockwise, the triangle scaled so that its side c spans p-q as placed: its shape, and so
// its orientation, are its own even where p-q was placed by a neighbour whose length of that side
// differs by rounding. Where it differs by more (kPlacedMismatch), the third corner is placed from
// p at the triangle's own size (still counter-clockwise; only the side p-q keeps the neighbour's
// length): scaled, it would hand the mismatch on to the faces drawn from it, multiplied at every
// such step (the arm's chart of 14 pieces of one needle, 4.5e-7 in area, grew to 2.8e8).
Eigen::Vector2d third_corner(const Eigen::Vector2d& p, const Eigen::Vector2d& q, double a, double b,
                             double c) {
  const Eigen::Vector2d d = q - p;
  const double placed = d.norm();
  const auto [x, y] = triangle_apex(c, b, a);
  const Eigen::Vector2d along = d / placed, left(-along.y(), along.x());
  const double scale = placed / c;
  const bool by_rounding = scale > 1 / kPlacedMismatch && scale < kPlacedMismatch;
  return p + (by_rounding ? scale : 1.0) * (x * along + y * left);
}

// Faces by chart: connected across edges that are neither cut nor boundary.
std::vector<int> chart_of_faces(const Triangulation& mesh, const std::vector<char>& cut,
                                int& num_charts) {
  std::vector<int> chart(mesh.num_faces(), -1);
  num_charts = 0;
  for (int s = 0; s < mesh.num_faces(); ++s) {
    if (chart[s] >= 0) continue;
    std::queue<int> queue;
    queue.push(s);
    chart[s] = num_charts;
    while (!queue.empty()) {
      const int f = queue.front();
      queue.pop();
      for (int c = 0; c < 3; ++c) {
        const int t = mesh.twin(3 * f + c);
        if (t < 0 || cut[mesh.face_edge(f, c)] || chart[t / 3] >= 0) continue;
        chart[t / 3] = num_charts;
        queue.push(t / 3);
      }
    }
    ++num_charts;
  }
  return chart;
}

// Per chart, its face farthest (in faces) from the chart's border: the seed of its development.
std::vector<int> deepest_faces(const Triangulation& mesh, const std::vector<char>& cut,
                               const std::vector<int>& chart, int num_charts) {
  const int nf = mesh.num_faces();
  std::vector<int> depth(nf, -1);
  std::queue<int> queue;
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * f + c);
      if (t < 0 || cut[mesh.face_edge(f, c)]) {
        depth[f] = 0;
        queue.push(f);
        break;
      }
    }
  }
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop();
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * f + c);
      if (t < 0 || cut[mesh.face_edge(f, c)] || depth[t / 3] >= 0) continue;
      depth[t / 3] = depth[f] + 1;
      queue.push(t / 3);
    }
  }
  std::vector<int> seed(num_charts, -1);
  for (int f = 0; f < nf; ++f) {
    int& s = seed[chart[f]];
    if (s < 0 || depth[f] > depth[s]) s = f;
  }
  return seed;
}

}  // namespace

Charts lay_out_charts(const Triangulation& mesh, const std::vector<double>& lengths,
                      const std::vector<char>& cut) {
  std::vector<std::array<double, 3>> sides(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) sides[f][c] = lengths[mesh.face_edge(f, c)];
  }
  return lay_out_charts(mesh, sides, cut);
}

double signed_area(const std::array<Eigen::Vector2d, 3>& t) {
  const Eigen::Vector2d a = t[1] - t[0], b = t[2] - t[0];
  return 0.5 * (a.x() * b.y() - a.y() * b.x());
}

std::vector<int> chart_wedges(const Triangulation& mesh, const std::vector<char>& cut) {
  const int nf = mesh.num_faces();
  detail::UnionFind wedges(3 * nf);
  for (int h = 0; h < 3 * nf; ++h) {
    const int t = mesh.twin(h);
    if (t < h || cut[mesh.face_edge(h / 3, h % 3)]) continue;
    for (int v : {mesh.halfedge_tail(h), mesh.halfedge_head(h)}) {
      wedges.unite(3 * (h / 3) + detail::corner_of(mesh, h / 3, v),
                   3 * (t / 3) + detail::corner_of(mesh, t / 3, v));
    }
  }
  std::vector<int> wedge(3 * nf);
  for (int k = 0; k < 3 * nf; ++k) wedge[k] = wedges.find(k);
  return wedge;
}

namespace {

// Develops each chart from its deepest face, reaching faces across the longest side that joins
// them to a placed one first (a maximum spanning tree of the dual graph): a sliver placed from its
// short side would turn the error of that side's ends into an error of its far corner larger by
// their ratio, and hand it on to its neighbours. Drawn from a long side instead, it turns over
// only where its width is below the rounding of its placement (cura-zav-maxpro's atlas: pieces
// 1e-8 wide and 5e-4 long, 4 turned when drawn breadth first). `draw(g, d, corners)` draws face
// g's corner d where its corners d+1 and d+2 are placed (d = -1: the seed, all three). Then every
// wedge goes to the mean of its corners, and the sides are measured against `sides`.
template <class Draw>
Charts develop_charts(const Triangulation& mesh, const std::vector<std::array<double, 3>>& sides,
                      const std::vector<char>& cut, const Draw& draw) {
  const int nf = mesh.num_faces();
  Charts charts;
  charts.chart = chart_of_faces(mesh, cut, charts.num_charts);
  charts.corners.assign(nf, {});
  const std::vector<int> seeds = deepest_faces(mesh, cut, charts.chart, charts.num_charts);
  std::vector<char> placed(nf, 0);
  auto& p = charts.corners;
  using Step = std::pair<double, int>;  // (length of the side crossed, halfedge crossed from)
  std::priority_queue<Step> queue;
  const auto reach_from = [&](int f) {
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * f + c);
      if (t >= 0 && !cut[mesh.face_edge(f, c)] && !placed[t / 3])
        queue.emplace(sides[f][c], 3 * f + c);
    }
  };
  for (int seed : seeds) {
    draw(seed, -1, p[seed]);
    placed[seed] = 1;
    reach_from(seed);
    while (!queue.empty()) {
      const int h = queue.top().second;
      queue.pop();
      const int f = h / 3, c = h % 3, t = mesh.twin(h);
      if (placed[t / 3]) continue;
      // Halfedge 3f + c runs from corner c+1 to c+2; its twin in g from d+1 to d+2 the other way.
      const int g = t / 3, d = t % 3;
      p[g][(d + 1) % 3] = p[f][(c + 2) % 3];
      p[g][(d + 2) % 3] = p[f][(c + 1) % 3];
      draw(g, d, p[g]);
      placed[g] = 1;
      reach_from(g);
    }
  }
  // Each wedge at the mean of its corners.
  const std::vector<int> wedge = chart_wedges(mesh, cut);
  std::vector<Eigen::Vector2d> sum(3 * nf, Eigen::Vector2d::Zero());
  std::vector<int> count(3 * nf, 0);
  for (int k = 0; k < 3 * nf; ++k) {
    sum[wedge[k]] += p[k / 3][k % 3];
    ++count[wedge[k]];
  }
  for (int k = 0; k < 3 * nf; ++k) p[k / 3][k % 3] = sum[wedge[k]] / count[wedge[k]];
  for (int h = 0; h < 3 * nf; ++h) {
    const double l = sides[h / 3][h % 3];
    const double drawn = (p[h / 3][(h % 3 + 1) % 3] - p[h / 3][(h % 3 + 2) % 3]).norm();
    charts.max_relative_length_error =
        std::max(charts.max_relative_length_error, std::abs(drawn / l - 1));
  }
  for (int f = 0; f < nf; ++f) charts.flipped_faces += !(signed_area(p[f]) > 0);
  return charts;
}

}  // namespace

Charts lay_out_charts(const Triangulation& mesh, const std::vector<std::array<double, 3>>& sides,
                      const std::vector<char>& cut) {
  return develop_charts(mesh, sides, cut, [&](int g, int d, std::array<Eigen::Vector2d, 3>& p) {
    const auto& l = sides[g];
    if (d < 0) {
      p[0] = Eigen::Vector2d::Zero();
      p[1] = Eigen::Vector2d(l[2], 0);
      d = 2;
    }
    const int i = (d + 1) % 3, j = (d + 2) % 3;
    p[d] = third_corner(p[i], p[j], l[i], l[j], l[d]);
  });
}

Charts lay_out_charts(const Triangulation& mesh,
                      const std::vector<std::array<Eigen::Vector2d, 3>>& drawn,
                      const std::vector<char>& cut) {
  std::vector<std::array<double, 3>> sides(drawn.size());
  for (size_t f = 0; f < drawn.size(); ++f) {
    for (int c = 0; c < 3; ++c)
      sides[f][c] = (drawn[f][(c + 1) % 3] - drawn[f][(c + 2) % 3]).norm();
  }
  return develop_charts(mesh, sides, cut, [&](int g, int d, std::array<Eigen::Vector2d, 3>& p) {
    const auto& q = drawn[g];
    if (d < 0) {
      p = q;
      return;
    }
    // The rigid motion that puts g's own side (corners d+1, d+2) onto the
    // placed one, about the sides' midpoints.
    const int i = (d + 1) % 3, j = (d + 2) % 3;
    const Eigen::Vector2d own = q[j] - q[i], placed = p[j] - p[i];
    const double scale = own.norm() * placed.norm();  // 0: no turn, a translation
    const double cos = scale > 0 ? own.dot(placed) / scale : 1;
    const double sin = scale > 0 ? cross(own, placed) / scale : 0;
    const Eigen::Vector2d r = q[d] - (q[i] + q[j]) / 2;
    p[d] =
        (p[i] + p[j]) / 2 + Eigen::Vector2d(cos * r.x() - sin * r.y(), sin * r.x() + cos * r.y());
  });
}

}  // namespace ricci
