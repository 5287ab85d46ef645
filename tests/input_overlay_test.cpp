// The input's edges followed through Ptolemy flips (subdivision/input_overlay.h), checked against
// a picture of the hyperbolic surface built here: an ideal quadrilateral inscribed in the unit
// circle (the Klein model), whose triangles are the lambda-length triangles up to the projective
// map b_v -> b_v / sigma_v^2 (sigma_v: the vertex's scale in the picture). The flipped diagonal
// and the input edge it replaces are then straight chords, and where they cross is known.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include <Eigen/LU>

#include "ricci/mesh/compact_mesh.h"
#include "subdivision/input_overlay.h"

namespace ricci {
namespace {

using Vec2 = Eigen::Vector2d;

struct Picture {
  std::array<Vec2, 4> z;  // k, a, l, b on the unit circle, counter-clockwise
  std::array<double, 4> sigma;
  double lambda(int i, int j) const { return (z[i] - z[j]).norm() / (sigma[i] * sigma[j]); }
  // The lambda-length barycentric coordinate of j on segment i-j of the point with picture
  // coordinate x there.
  double lambda_parameter(int i, int j, double x) const {
    const double bi = (1 - x) * sigma[i] * sigma[i], bj = x * sigma[j] * sigma[j];
    return bj / (bi + bj);
  }
};

// Where chords p0-p1 and q0-q1 cross: the parameters along each.
std::array<double, 2> chord_crossing(const Vec2& p0, const Vec2& p1, const Vec2& q0,
                                     const Vec2& q1) {
  Eigen::Matrix2d m;
  m.col(0) = p1 - p0;
  m.col(1) = q0 - q1;
  const Vec2 x = m.partialPivLu().solve(q0 - p0);
  return {x[0], x[1]};
}

// A planar mesh of the two lambda-length triangles (k, a, b) and (l, b, a) glued along a-b: only
// its connectivity matters to the overlay.
CompactMesh quad_mesh(const Picture& p) {
  enum { K = 0, A = 1, L = 2, B = 3 };
  const double ab = p.lambda(A, B), ka = p.lambda(K, A), kb = p.lambda(K, B);
  const double la = p.lambda(L, A), lb = p.lambda(L, B);
  auto apex = [&](double to_a, double to_b, double side) {
    const double x = (to_a * to_a - to_b * to_b + ab * ab) / (2 * ab);
    return Eigen::Vector3d(x, side * std::sqrt(std::max(0.0, to_a * to_a - x * x)), 0);
  };
  // a at the origin, b on the x axis: k below (so k, a, b is counter-clockwise), l above.
  std::vector<Eigen::Vector3d> positions = {apex(ka, kb, -1), Eigen::Vector3d::Zero(),
                                            apex(la, lb, 1), Eigen::Vector3d(ab, 0, 0)};
  return CompactMesh(positions, {{K, B, A}, {L, A, B}});
}

TEST(InputOverlay, APtolemyFlipCrossesTheInputEdgeWhereTheGeodesicsMeet) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0, 1), scale(0.4, 2.5);
  int tested = 0;
  for (int trial = 0; trial < 400; ++trial) {
    Picture p;
    // Angles in order around the circle: k, a, l, b counter-clockwise.
    std::array<double, 4> angle{};
    double at = 0;
    for (double& x : angle) x = at += 0.15 + unit(random);
    const double turn = at + 0.15 + unit(random);
    for (int i = 0; i < 4; ++i) {
      const double theta = 2 * M_PI * angle[i] / turn;
      p.z[i] = Vec2(std::cos(theta), std::sin(theta));
      p.sigma[i] = scale(random);
    }
    // The input's faces are lambda-length triangles: both must be proper ones.
    auto proper = [&](int i, int j, int k) {
      const double x = p.lambda(i, j), y = p.lambda(j, k), w = p.lambda(k, i);
      return x + y > 1.01 * w && y + w > 1.01 * x && w + x > 1.01 * y;
    };
    if (!proper(0, 1, 3) || !proper(2, 3, 1)) continue;
    ++tested;
    const CompactMesh mesh = quad_mesh(p);
    int e = -1;
    for (int i = 0; i < mesh.num_edges(); ++i) {
      const auto ends = mesh.edge_vertices(i);
      if (std::min(ends[0], ends[1]) == 1 && std::max(ends[0], ends[1]) == 3) e = i;  // a-b
    }
    ASSERT_GE(e, 0);
    // The record as the flow writes it (flip_record): the quadrilateral k, a, l, b read from the
    // halfedge of a-b, its sides k-a, a-l, l-b, b-k, then the diagonal.
    const int h = mesh.edge_halfedge(e), tw = mesh.twin(h);
    const int k = mesh.face_vertex(h / 3, h % 3), a = mesh.face_vertex(h / 3, (h % 3 + 1) % 3),
              b = mesh.face_vertex(h / 3, (h % 3 + 2) % 3), l = mesh.face_vertex(tw / 3, tw % 3);
    EdgeFlip record;
    record.edge = e;
    record.ptolemy = true;
    record.lambda = {p.lambda(k, a), p.lambda(a, l), p.lambda(l, b), p.lambda(b, k),
                     p.lambda(a, b)};
    record.chord = record.lambda;
    detail::InputOverlay overlay(mesh, true);
    overlay.flip(record);

    const auto [along_kl, along_ab] = chord_crossing(p.z[0], p.z[2], p.z[1], p.z[3]);
    int live = 0;
    for (const detail::Crossing& x : overlay.crossings()) {
      if (!x.alive) continue;
      ++live;
      ASSERT_EQ(x.input_edge, e);
      const auto input_ends = mesh.edge_vertices(e);
      const auto ends = overlay.triangulation().edge_vertices(x.edge);
      ASSERT_EQ(std::min(ends[0], ends[1]), 0) << "the new edge is k-l";
      ASSERT_EQ(std::max(ends[0], ends[1]), 2) << "the new edge is k-l";
      // s from input_ends[0], t from ends[0], each a lambda-length barycentric coordinate.
      const double s = input_ends[0] == 1 ? p.lambda_parameter(1, 3, along_ab)
                                          : p.lambda_parameter(3, 1, 1 - along_ab);
      const double t = ends[0] == 0 ? p.lambda_parameter(0, 2, along_kl)
                                    : p.lambda_parameter(2, 0, 1 - along_kl);
      EXPECT_NEAR(x.s, s, 1e-12) << "trial " << trial;
      EXPECT_NEAR(x.t, t, 1e-12) << "trial " << trial;
    }
    EXPECT_EQ(live, 1);
  }
  EXPECT_GE(tested, 100);
}

}  // namespace
}  // namespace ricci
