// Development of a metric into its model, triangle by triangle (H2 and S2 layouts, and the first
// step of E2 ones, plane_layout.cpp).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <queue>
#include <utility>

#include <Eigen/Geometry>

#include "layout/layout_methods.h"

namespace ricci::detail {

namespace {

using Complex = std::complex<double>;

Complex to_complex(const Eigen::Vector3d& p) {
  return {p.x(), p.y()};
}
Eigen::Vector3d from_complex(Complex z) {
  return {z.real(), z.imag(), 0.0};
}

// C such that (A, B, C) is counter-clockwise, |AC| = l_ac and the angle at A is alpha.
Eigen::Vector3d place_third(Geometry g, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            double l_ac, double alpha) {
  switch (g) {
    case Geometry::Euclidean: {
      const Complex dir = std::polar(1.0, std::arg(to_complex(b) - to_complex(a)) + alpha);
      return from_complex(to_complex(a) + l_ac * dir);
    }
    case Geometry::Hyperbolic: {
      const DiskIsometry m = DiskIsometry::moving_to_origin(to_complex(a));
      const Complex c = std::polar(std::tanh(l_ac / 2), std::arg(m(to_complex(b))) + alpha);
      return from_complex(m.inverse()(c));
    }
    case Geometry::Spherical: {
      const Eigen::Vector3d t = (b - a.dot(b) * a).normalized();
      const Eigen::Vector3d turned = std::cos(alpha) * t + std::sin(alpha) * a.cross(t);
      return (std::cos(l_ac) * a + std::sin(l_ac) * turned).normalized();
    }
  }
  return a;
}

double disk_distance(Complex a, Complex b) {
  return std::acosh(1 + 2 * std::norm(a - b) / ((1 - std::norm(a)) * (1 - std::norm(b))));
}

// H2 developments run in long double and are rounded to double once per corner: each face is placed
// from two corners placed before, so in double the rounding of every step was handed on along the
// development, and the copies of a vertex on the two sides of the cut, reached along different
// paths, met only to the rounding those paths had gathered (openscad-tardis.stl's angle sums at
// its cut: 1.0e-8, 3.5e-9 in long double).
using LongComplex = std::complex<long double>;

LongComplex long_of(Complex z) {
  return {z.real(), z.imag()};
}
Complex double_of(LongComplex z) {
  return {static_cast<double>(z.real()), static_cast<double>(z.imag())};
}
LongComplex apply(const DiskIsometry& m, LongComplex z) {
  const LongComplex a = long_of(m.a), b = long_of(m.b);
  return (a * z + b) / (std::conj(b) * z + std::conj(a));
}

// H2: C such that (A, B, C) is counter-clockwise, |AC| = l_ac and the angle at A is alpha.
LongComplex place_third_in_disk(LongComplex a, LongComplex b, double l_ac, double alpha) {
  const LongComplex one = 1;
  const LongComplex mb = (b - a) / (one - std::conj(a) * b);  // b with a moved to the centre
  const LongComplex c =
      std::polar(std::tanh(static_cast<long double>(l_ac) / 2), std::arg(mb) + alpha);
  return (c + a) / (one + std::conj(a) * c);
}

// The face deepest inside the cut disk: farthest, in faces, from every cut and boundary edge.
int deepest_face(const Triangulation& mesh, const std::vector<char>& cut) {
  const int nf = mesh.num_faces();
  std::vector<int> depth(nf, -1);
  std::queue<int> queue;
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int e = mesh.face_edge(f, c);
      if (mesh.is_boundary_edge(e) || cut[e]) {
        depth[f] = 0;
        queue.push(f);
        break;
      }
    }
  }
  if (queue.empty()) return 0;
  int last = queue.front();
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop();
    last = f;
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * f + c);
      if (t < 0 || cut[mesh.face_edge(f, c)] || depth[t / 3] >= 0) continue;
      depth[t / 3] = depth[f] + 1;
      queue.push(t / 3);
    }
  }
  return last;
}

// From the placed seed across uncut edges, each face from the two corners it shares with a placed
// face, nearest to the seed first (Dijkstra on the dual, each step from the middle of the side a
// face was entered by to that of the side it is left by). The paths to a vertex's copies on the
// two sides of the cut then run close to the geodesics to them: the flow's residual curvature
// between two paths turns one copy against the other (breadth first, CGAL's refined_elephant.off
// had its angle sums off 2 pi by 3.6e-8 at its cut, 1.5e-8 so; polygon_mesh.off 5.0e-8 and
// 3.0e-9; the rest was welding, weld_corner_copies). In charts (H2): a face that would be placed
// beyond the chart radius from its chart's centre goes into a chart of the same parent
// (ChartGrowth); its two shared corners are moved into that chart by the transition, its third
// corner placed there.
void develop_faces(const Triangulation& mesh, Geometry geometry, const std::vector<double>& lengths,
                   const std::vector<std::array<double, 3>>& angles, int seed, bool in_charts,
                   Layout& layout) {
  const int nf = mesh.num_faces();
  auto& p = layout.corners;
  std::optional<ChartGrowth> charts;
  if (in_charts) {
    charts.emplace(layout, layout.chart_radius);
    layout.chart.assign(nf, -1);
    layout.chart[seed] = 0;
  }
  // H2: the corners in long double as developed.
  const bool disk = geometry == Geometry::Hyperbolic;
  std::vector<std::array<LongComplex, 3>> q(disk ? nf : 0);
  if (disk) {
    for (int c = 0; c < 3; ++c) q[seed][c] = long_of(to_complex(p[seed][c]));
  }
  // Dijkstra on the dual: each face's distance from the seed along the development, from the
  // middle of the side it was entered by to that of the side it is left by.
  std::vector<char> placed(nf, 0);
  std::vector<double> distance(nf, 0);
  std::vector<Eigen::Vector3d> entry(nf);
  // (Beyond about 37, |z| rounds to 1 in the first, one-chart pass: infinite, never NaN, so that
  // the queue's order stays one.)
  const auto gap = [&](const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
    const double d = disk ? disk_distance(to_complex(x), to_complex(y)) : (x - y).norm();
    return std::isnan(d) ? std::numeric_limits<double>::infinity() : d;
  };
  using Step = std::pair<double, int>;  // (distance from the seed, halfedge crossed from)
  std::priority_queue<Step, std::vector<Step>, std::greater<>> queue;
  const auto reach_from = [&](int f) {
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * f + c);
      if (t < 0 || layout.cut.cut[mesh.face_edge(f, c)] || placed[t / 3]) continue;
      const Eigen::Vector3d middle = (p[f][(c + 1) % 3] + p[f][(c + 2) % 3]) / 2;
      queue.emplace(distance[f] + gap(entry[f], middle), 3 * f + c);
    }
  };
  placed[seed] = 1;
  entry[seed] = (p[seed][0] + p[seed][1] + p[seed][2]) / 3;
  reach_from(seed);
  while (!queue.empty()) {
    const auto [key, h] = queue.top();
    queue.pop();
    const int f = h / 3, c = h % 3, t = mesh.twin(h);
    if (placed[t / 3]) continue;
    const int g = t / 3, ct = t % 3, c1 = (ct + 1) % 3, c2 = (ct + 2) % 3;
    distance[g] = key;
    const double side = lengths[mesh.face_edge(g, c2)];
    if (disk) {
      LongComplex a = q[f][(c + 2) % 3], b = q[f][(c + 1) % 3];
      LongComplex x = place_third_in_disk(a, b, side, angles[g][c1]);
      if (charts) {
        const int k = layout.chart[f], j = charts->chart_for(k, double_of(x));
        if (j != k) {
          const DiskIsometry& move = layout.chart_from_parent[static_cast<size_t>(j)];
          a = apply(move, a);
          b = apply(move, b);
          x = place_third_in_disk(a, b, side, angles[g][c1]);
        }
        layout.chart[g] = j;
      }
      q[g][c1] = a;
      q[g][c2] = b;
      q[g][ct] = x;
      for (int k = 0; k < 3; ++k) p[g][k] = from_complex(double_of(q[g][k]));
      placed[g] = 1;
      entry[g] = (p[g][c1] + p[g][c2]) / 2;
      reach_from(g);
      continue;
    }
    // S2 (never in charts).
    const Eigen::Vector3d a = p[f][(c + 2) % 3], b = p[f][(c + 1) % 3];
    const Eigen::Vector3d x = place_third(geometry, a, b, side, angles[g][c1]);
    p[g][c1] = a;
    p[g][c2] = b;
    p[g][ct] = x;
    placed[g] = 1;
    entry[g] = (a + b) / 2;
    reach_from(g);
  }
}

}  // namespace

ChartGrowth::ChartGrowth(Layout& layout, double chart_radius)
    : layout_(layout), rim_(std::tanh(chart_radius / 2)), centre_{0.0}, children_(1) {
  layout_.chart_radius = chart_radius;
  layout_.chart_parent = {-1};
  layout_.chart_from_parent = {DiskIsometry{Geometry::Hyperbolic, 1.0, 0.0}};
}

int ChartGrowth::chart_for(int k, Complex z) {
  if (std::abs(z) <= rim_) return k;
  for (int child : children_[static_cast<size_t>(k)]) {
    if (disk_distance(centre_[static_cast<size_t>(child)], z) < layout_.chart_radius / 2) {
      return child;
    }
  }
  const int j = static_cast<int>(centre_.size());
  centre_.push_back(z);
  children_[static_cast<size_t>(k)].push_back(j);
  children_.emplace_back();
  layout_.chart_parent.push_back(k);
  layout_.chart_from_parent.push_back(DiskIsometry::moving_to_origin(z));
  return j;
}

Layout develop(const Triangulation& mesh, Geometry geometry, const std::vector<double>& lengths,
               double chart_radius) {
  const int nf = mesh.num_faces();
  const std::vector<std::array<double, 3>> angles = face_angles(mesh, geometry, lengths);
  Layout layout;
  layout.geometry = geometry;
  // H2: the cut of shortest paths from a central face, developed from that face, keeps the
  // layout near the Poincare disk's centre (precision); S2 keeps the combinatorial cut.
  layout.cut = geometry == Geometry::Hyperbolic ? cut_to_disk(mesh, lengths) : cut_to_disk(mesh);
  layout.corners.assign(nf, {});
  if (nf == 0) return layout;
  const int seed =
      geometry == Geometry::Hyperbolic ? layout.cut.root : deepest_face(mesh, layout.cut.cut);

  // --- the seed face, then across uncut edges nearest first; H2 again in charts where the domain
  // reaches beyond kOneChartRadius
  const auto edge_length_at = [&](int f, int corner) { return lengths[mesh.face_edge(f, corner)]; };
  auto& p = layout.corners;
  if (geometry == Geometry::Spherical) {
    p[seed][0] = Eigen::Vector3d(0, 0, 1);
    const double l = edge_length_at(seed, 2);
    p[seed][1] = Eigen::Vector3d(std::sin(l), 0, std::cos(l));
  } else {
    const double l = edge_length_at(seed, 2);
    p[seed][0] = Eigen::Vector3d::Zero();
    p[seed][1] = Eigen::Vector3d(geometry == Geometry::Hyperbolic ? std::tanh(l / 2) : l, 0, 0);
  }
  p[seed][2] =
      place_third(geometry, p[seed][0], p[seed][1], edge_length_at(seed, 1), angles[seed][0]);
  develop_faces(mesh, geometry, lengths, angles, seed, false, layout);
  if (geometry == Geometry::Hyperbolic) {
    double far = 0;
    for (const auto& face : p) {
      for (const auto& z : face) far = std::max(far, z.norm());
    }
    layout.reach = 2 * std::atanh(std::min(far, 1 - 1e-16));
    if (layout.reach > kOneChartRadius) {
      layout.chart_radius = chart_radius;
      develop_faces(mesh, geometry, lengths, angles, seed, true, layout);
    }
  }
  return layout;
}

}  // namespace ricci::detail
