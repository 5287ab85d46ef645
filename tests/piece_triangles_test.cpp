// The triangles a piece of the common subdivision is delivered as: checked against every
// triangulation of the polygon, with quasi-conformal ratios computed here by an SVD.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include <Eigen/Dense>

#include "subdivision/piece_triangles.h"

namespace ricci::detail {
namespace {

using Vec2 = Eigen::Vector2d;
using Triangles = std::vector<std::array<size_t, 3>>;

double signed_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  return 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
}

// Larger over smaller singular value of the affine map from a to b, or infinity where either is
// flat or the map turns it.
double svd_ratio(const std::array<Vec2, 3>& a, const std::array<Vec2, 3>& b) {
  if (signed_area(a[0], a[1], a[2]) <= 0 || signed_area(b[0], b[1], b[2]) <= 0)
    return std::numeric_limits<double>::infinity();
  Eigen::Matrix2d A, B;
  A << a[1] - a[0], a[2] - a[0];
  B << b[1] - b[0], b[2] - b[0];
  const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix2d>(B * A.inverse()).singularValues();
  return s[0] / s[1];
}

// The sum the triangles minimize: (log K)^2 of each one's map.
double objective(const Triangles& t, const std::vector<Vec2>& x, const std::vector<Vec2>& y) {
  double sum = 0;
  for (const auto& k : t) {
    const double r = svd_ratio({x[k[0]], x[k[1]], x[k[2]]}, {y[k[0]], y[k[1]], y[k[2]]});
    sum += std::log(r) * std::log(r);
  }
  return sum;
}

// Every triangulation of the polygon i..j closed by the side (i, j).
std::vector<Triangles> all_triangulations(size_t i, size_t j) {
  if (j - i < 2) return {Triangles{}};
  std::vector<Triangles> out;
  for (size_t k = i + 1; k < j; ++k) {
    for (const Triangles& left : all_triangulations(i, k)) {
      for (const Triangles& right : all_triangulations(k, j)) {
        Triangles t = left;
        t.insert(t.end(), right.begin(), right.end());
        t.push_back({i, k, j});
        out.push_back(t);
      }
    }
  }
  return out;
}

// The image of p under a projective map that keeps the unit square's neighbourhood in front.
Vec2 projective(const Vec2& p, double a, double b) {
  const double w = 1 + a * p.x() + b * p.y();
  return Vec2(1.3 * p.x() + 0.4 * p.y(), 0.2 * p.x() + 0.9 * p.y()) / w;
}

// Random convex polygons of 3 to 7 corners and their images under projective maps: the triangles
// cover the polygon once in both pictures, and (nearest to conformal) no triangulation has a
// smaller sum.
void expect_cover(PieceTriangles how) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15), tilt(-0.4, 0.4);
  for (int trial = 0; trial < 200; ++trial) {
    const size_t n = 3 + static_cast<size_t>(trial % 5);
    std::vector<Vec2> domain, image;
    for (size_t i = 0; i < n; ++i) {  // corners on an ellipse, jittered in angle
      const double angle =
          2 * M_PI * (static_cast<double>(i) + 0.4 * jitter(random)) / static_cast<double>(n);
      domain.emplace_back(0.5 + 0.5 * std::cos(angle), 0.5 + 0.3 * std::sin(angle));
    }
    const double a = tilt(random), b = tilt(random);
    for (const Vec2& p : domain) image.push_back(projective(p, a, b));
    const Triangles got = piece_triangles(domain, image, how);
    ASSERT_EQ(got.size(), n - 2);
    std::set<size_t> corners;
    double area_x = 0, area_y = 0;
    for (const auto& k : got) {
      EXPECT_GT(signed_area(domain[k[0]], domain[k[1]], domain[k[2]]), 0);
      EXPECT_GT(signed_area(image[k[0]], image[k[1]], image[k[2]]), 0);
      corners.insert(k.begin(), k.end());
      area_x += signed_area(domain[k[0]], domain[k[1]], domain[k[2]]);
      area_y += signed_area(image[k[0]], image[k[1]], image[k[2]]);
    }
    EXPECT_EQ(corners.size(), n);
    double polygon_x = 0, polygon_y = 0;
    for (size_t i = 1; i + 1 < n; ++i) {
      polygon_x += signed_area(domain[0], domain[i], domain[i + 1]);
      polygon_y += signed_area(image[0], image[i], image[i + 1]);
    }
    EXPECT_NEAR(area_x, polygon_x, 1e-12);
    EXPECT_NEAR(area_y, polygon_y, 1e-12);
    if (how != PieceTriangles::NearestToConformal) continue;
    double best = std::numeric_limits<double>::infinity();
    for (const Triangles& t : all_triangulations(0, n - 1))
      best = std::min(best, objective(t, domain, image));
    EXPECT_NEAR(objective(got, domain, image), best, 1e-12 * (1 + best)) << "trial " << trial;
  }
}

TEST(PieceTriangles, AreTheTriangulationNearestToConformal) {
  expect_cover(PieceTriangles::NearestToConformal);
}

TEST(PieceTriangles, OrRoundEarsThatCoverThePiece) {
  expect_cover(PieceTriangles::Roundest);
}

TEST(PieceTriangles, NoTriangleIsFlatWherePointsLieOnASide) {
  // A square whose bottom side holds three more points: every fan from a bottom point has flat
  // triangles; only apexes at the top corners make none.
  const std::vector<Vec2> domain = {{0, 0}, {0.25, 0}, {0.5, 0}, {0.75, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<Vec2> image;
  for (const Vec2& p : domain) image.push_back(projective(p, 0.3, -0.2));
  for (const PieceTriangles how : {PieceTriangles::NearestToConformal, PieceTriangles::Roundest}) {
    const Triangles got = piece_triangles(domain, image, how);
    ASSERT_EQ(got.size(), domain.size() - 2);
    for (const auto& k : got) {
      EXPECT_GT(signed_area(domain[k[0]], domain[k[1]], domain[k[2]]), 1e-3);
      EXPECT_GT(signed_area(image[k[0]], image[k[1]], image[k[2]]), 1e-3);
    }
  }
}

TEST(PieceTriangles, RoundEarsCutAKiteAtItsShorterDiagonal) {
  // Either diagonal draws the kite's map (a similarity) conformally; the long one, a fan's from
  // the first corner, leaves two needles, which an atlas's harmonic redrawing would squash.
  const std::vector<Vec2> domain = {{10, 0}, {5, 0.4}, {0, 0}, {5, -0.4}};
  std::vector<Vec2> image;
  for (const Vec2& p : domain) image.emplace_back(2 * p.x() - p.y() + 1, p.x() + 2 * p.y());
  const Triangles got = piece_triangles(domain, image, PieceTriangles::Roundest);
  ASSERT_EQ(got.size(), 2u);
  for (const auto& k : got) {
    const std::set<size_t> corners(k.begin(), k.end());
    EXPECT_TRUE(corners.count(1) && corners.count(3)) << "the diagonal 1-3, not 0-2";
  }
}

TEST(PieceTriangles, AnImageTurnedOverGetsTheRoundEars) {
  const std::vector<Vec2> domain = {{0, 0}, {1, 0}, {1.2, 1}, {0, 1}};
  std::vector<Vec2> image;
  for (const Vec2& p : domain) image.emplace_back(p.x(), -p.y());
  EXPECT_TRUE(std::isinf(
      quasi_conformal_ratio({domain[0], domain[1], domain[2]}, {image[0], image[1], image[2]})));
  const Triangles ears = piece_triangles(domain, image, PieceTriangles::Roundest);
  EXPECT_EQ(piece_triangles(domain, image, PieceTriangles::NearestToConformal), ears);
  ASSERT_EQ(ears.size(), 2u);
  for (const auto& k : ears) EXPECT_GT(signed_area(domain[k[0]], domain[k[1]], domain[k[2]]), 0.1);
}

TEST(PieceTriangles, AnImageCornerTurnedInwardRulesOutTheDiagonalsThatTurnOver) {
  // A square drawn with corner 1 pushed inside: the triangle (0, 1, 2) turns over, so the only
  // triangulation with none turned is the one at the diagonal 1-3.
  const std::vector<Vec2> domain = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const std::vector<Vec2> image = {{0, 0}, {0.4, 0.6}, {1, 1}, {0, 1}};
  const Triangles got = piece_triangles(domain, image, PieceTriangles::NearestToConformal);
  ASSERT_EQ(got.size(), 2u);
  for (const auto& k : got) {
    const std::set<size_t> corners(k.begin(), k.end());
    EXPECT_TRUE(corners.count(1) && corners.count(3));
    EXPECT_GT(signed_area(image[k[0]], image[k[1]], image[k[2]]), 0);
  }
}

TEST(PieceTriangles, CoincidentCornersStillGiveAllTriangles) {
  const std::vector<Vec2> domain = {{0, 0}, {1, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const PieceTriangles how : {PieceTriangles::NearestToConformal, PieceTriangles::Roundest}) {
    const Triangles got = piece_triangles(domain, domain, how);
    ASSERT_EQ(got.size(), 3u);
    std::set<size_t> corners;
    for (const auto& k : got) corners.insert(k.begin(), k.end());
    EXPECT_EQ(corners.size(), 5u);
  }
}

TEST(PieceTriangles, RatioHoldsForNeedlesAndNearlyConformalMaps) {
  // A needle sheared along itself: J = [[1, 1e9], [0, 1]], whose singular values' ratio is
  // (s + sqrt(s^2 - 4)) / 2 with s = 2 + 1e18, about 1e18; the same turned by any angle.
  const std::array<Vec2, 3> a = {Vec2(0, 0), Vec2(1, 0), Vec2(0.5, 1e-7)};
  const std::array<Vec2, 3> b = {Vec2(0, 0), Vec2(1, 0), Vec2(100.5, 1e-7)};
  for (int k = 0; k < 24; ++k) {
    const Eigen::Rotation2Dd turn(0.27 * k), other(-0.61 * k);
    std::array<Vec2, 3> ta, tb;
    for (int i = 0; i < 3; ++i) ta[i] = turn * a[i], tb[i] = other * b[i];
    const double ratio = quasi_conformal_ratio(ta, tb);
    EXPECT_NEAR(ratio / 1e18, 1, 1e-6) << "turn " << k;
  }
  // A shear by 1e-9: K - 1 = 1e-9 to first order, which s^2 - 4 det^2 would cancel to 0.
  const std::array<Vec2, 3> c = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)};
  const std::array<Vec2, 3> d = {Vec2(0, 0), Vec2(1, 0), Vec2(1e-9, 1)};
  EXPECT_NEAR(quasi_conformal_ratio(c, d) - 1, 1e-9, 1e-14);
}

TEST(PieceTriangles, RatioIsTheSingularValuesRatio) {
  const std::array<Vec2, 3> a = {Vec2(0, 0), Vec2(2, 0.3), Vec2(0.5, 1.1)};
  const std::array<Vec2, 3> b = {Vec2(1, 1), Vec2(1.4, 2.9), Vec2(-0.6, 1.7)};
  EXPECT_NEAR(quasi_conformal_ratio(a, b), svd_ratio(a, b), 1e-12);
  EXPECT_NEAR(quasi_conformal_ratio(a, a), 1.0, 1e-12);
}

}  // namespace
}  // namespace ricci::detail
