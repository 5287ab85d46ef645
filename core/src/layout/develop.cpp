// Development of a metric into its model, triangle by triangle (H2 and S2 layouts).
#include <algorithm>
#include <cmath>
#include <optional>
#include <queue>

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

// Breadth-first from the placed seed across uncut edges, each face from the two corners it shares
// with a placed face. In charts (H2): a face that would be placed beyond the chart radius from its
// chart's centre goes into a chart of the same parent whose centre is within half of it, or
// a new one centred where the face would go; its two shared corners are moved into that chart by
// the transition, its third corner placed there.
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
  std::vector<char> placed(nf, 0);
  placed[seed] = 1;
  std::queue<int> queue;
  queue.push(seed);
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop();
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * f + c);
      if (t < 0 || layout.cut.cut[mesh.face_edge(f, c)] || placed[t / 3]) continue;
      const int g = t / 3, ct = t % 3, c1 = (ct + 1) % 3, c2 = (ct + 2) % 3;
      const double side = lengths[mesh.face_edge(g, c2)];
      Eigen::Vector3d a = p[f][(c + 2) % 3], b = p[f][(c + 1) % 3];
      Eigen::Vector3d x = place_third(geometry, a, b, side, angles[g][c1]);
      if (charts) {
        const int k = layout.chart[f], j = charts->chart_for(k, to_complex(x));
        if (j != k) {
          const DiskIsometry& move = layout.chart_from_parent[static_cast<size_t>(j)];
          a = from_complex(move(to_complex(a)));
          b = from_complex(move(to_complex(b)));
          x = place_third(geometry, a, b, side, angles[g][c1]);
        }
        layout.chart[g] = j;
      }
      p[g][c1] = a;
      p[g][c2] = b;
      p[g][ct] = x;
      placed[g] = 1;
      queue.push(g);
    }
  }
}

double disk_distance(Complex a, Complex b) {
  return std::acosh(1 + 2 * std::norm(a - b) / ((1 - std::norm(a)) * (1 - std::norm(b))));
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

  // --- the seed face, then breadth-first across uncut edges; H2 again in charts where the domain
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
