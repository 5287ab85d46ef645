// Length law, cosine law and their derivatives in E2, H2, S2, checked against central finite
// differences on random configurations for every combination of eps.
#include "ricci/mesh/geometry.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace ricci {
namespace {

const Geometry kGeometries[] = {Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical};

TEST(Geometry, RadiusConformalFactorRoundTrip) {
  for (Geometry g : kGeometries) {
    for (double r : {0.01, 0.3, 1.0, 1.4}) {
      EXPECT_NEAR(radius_from_conformal_factor(g, conformal_factor_from_radius(g, r)), r, 1e-13)
          << to_string(g);
    }
  }
  EXPECT_TRUE(std::isnan(radius_from_conformal_factor(Geometry::Hyperbolic, 0.1)));
}

TEST(Geometry, TangentCirclesTouch) {
  // eps = 1, eta = 1: l = r_i + r_j in every geometry (DESIGN.md sanity check).
  for (Geometry g : kGeometries) {
    const double ri = 0.3, rj = 0.45;
    const EdgeLength e = edge_length(g, conformal_factor_from_radius(g, ri),
                                     conformal_factor_from_radius(g, rj), 1, 1, 1.0);
    ASSERT_TRUE(e.valid);
    EXPECT_NEAR(e.length, ri + rj, 1e-14) << to_string(g);
  }
}

TEST(Geometry, PaperLengthLawHolds) {
  // The cancellation-free form used in the code equals the paper's cosh l = ... / cos l = ...
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-2.0, -0.3), eta_dist(0.2, 3.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int ei = int(rng() % 3) - 1, ej = int(rng() % 3) - 1;
    const double ui = uni(rng), uj = uni(rng), eta = eta_dist(rng);
    const double a = ei * std::exp(2 * ui), b = ej * std::exp(2 * uj), c = std::exp(ui + uj);
    const EdgeLength e2 = edge_length(Geometry::Euclidean, ui, uj, ei, ej, eta);
    if (e2.valid) {
      EXPECT_NEAR(e2.length * e2.length, 2 * eta * c + a + b, 1e-12);
    }
    const EdgeLength h2 = edge_length(Geometry::Hyperbolic, ui, uj, ei, ej, eta);
    if (h2.valid) {
      EXPECT_NEAR(std::cosh(h2.length), (4 * eta * c + (1 + a) * (1 + b)) / ((1 - a) * (1 - b)),
                  1e-11);
    }
    const EdgeLength s2 = edge_length(Geometry::Spherical, ui, uj, ei, ej, eta);
    if (s2.valid) {
      EXPECT_NEAR(std::cos(s2.length), (-4 * eta * c + (1 - a) * (1 - b)) / ((1 + a) * (1 + b)),
                  1e-12);
    }
  }
}

TEST(Geometry, EdgeLengthDerivativesMatchFiniteDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-2.5, -0.2), eta_dist(0.1, 4.0);
  int checked = 0;
  for (Geometry g : kGeometries) {
    for (int ei = -1; ei <= 1; ++ei) {
      for (int ej = -1; ej <= 1; ++ej) {
        for (int trial = 0; trial < 20; ++trial) {
          const double ui = uni(rng), uj = uni(rng), eta = eta_dist(rng);
          const EdgeLength e = edge_length(g, ui, uj, ei, ej, eta);
          if (!e.valid) continue;
          const double h = 1e-6;
          const double fd_i = (edge_length(g, ui + h, uj, ei, ej, eta).length -
                               edge_length(g, ui - h, uj, ei, ej, eta).length) /
                              (2 * h);
          const double fd_j = (edge_length(g, ui, uj + h, ei, ej, eta).length -
                               edge_length(g, ui, uj - h, ei, ej, eta).length) /
                              (2 * h);
          EXPECT_NEAR(e.d_ui, fd_i, 1e-6 * std::max(1.0, std::abs(fd_i))) << to_string(g);
          EXPECT_NEAR(e.d_uj, fd_j, 1e-6 * std::max(1.0, std::abs(fd_j))) << to_string(g);
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 300);
}

TEST(Geometry, ConformalStructureInvertsLengthLaw) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> len(0.05, 1.2), uni(-2.0, -0.4);
  for (Geometry g : kGeometries) {
    for (int ei = -1; ei <= 1; ++ei) {
      for (int ej = -1; ej <= 1; ++ej) {
        const double l = len(rng), ui = uni(rng), uj = uni(rng);
        const double eta = conformal_structure_from_length(g, l, ui, uj, ei, ej);
        const EdgeLength e = edge_length(g, ui, uj, ei, ej, eta);
        ASSERT_TRUE(e.valid);
        EXPECT_NEAR(e.length / l, 1.0, 1e-13) << to_string(g) << " " << ei << ej;
      }
    }
  }
}

TEST(Geometry, CornerAnglesSatisfyCosineLaw) {
  const std::array<double, 3> l = {0.5, 0.6, 0.7};
  for (Geometry g : kGeometries) {
    const TriangleAngles t = corner_angles(g, l);
    ASSERT_TRUE(t.valid);
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      double expected_cos = 0;
      if (g == Geometry::Euclidean) {
        expected_cos = (l[j] * l[j] + l[k] * l[k] - l[i] * l[i]) / (2 * l[j] * l[k]);
      } else if (g == Geometry::Hyperbolic) {
        expected_cos = (std::cosh(l[j]) * std::cosh(l[k]) - std::cosh(l[i])) /
                       (std::sinh(l[j]) * std::sinh(l[k]));
      } else {
        expected_cos =
            (std::cos(l[i]) - std::cos(l[j]) * std::cos(l[k])) / (std::sin(l[j]) * std::sin(l[k]));
      }
      EXPECT_NEAR(std::cos(t.angle[i]), expected_cos, 1e-14) << to_string(g);
    }
    const double sum = t.angle[0] + t.angle[1] + t.angle[2];
    // Angle sum: pi in E2, below pi in H2 (defect = area), above pi in S2 (excess = area).
    if (g == Geometry::Euclidean) {
      EXPECT_NEAR(sum, kPi, 1e-14);
    } else if (g == Geometry::Hyperbolic) {
      EXPECT_LT(sum, kPi);
    } else {
      EXPECT_GT(sum, kPi);
    }
  }
}

TEST(Geometry, AngleDerivativesMatchFiniteDifferences) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> len(0.1, 1.0);
  int checked = 0;
  for (Geometry g : kGeometries) {
    for (int trial = 0; trial < 50; ++trial) {
      std::array<double, 3> l = {len(rng), len(rng), len(rng)};
      const TriangleAngles t = corner_angles(g, l);
      if (!t.valid) continue;
      for (int e = 0; e < 3; ++e) {
        const double h = 1e-6;
        auto lp = l, lm = l;
        lp[e] += h;
        lm[e] -= h;
        const TriangleAngles tp = corner_angles(g, lp), tm = corner_angles(g, lm);
        if (!tp.valid || !tm.valid) continue;
        for (int c = 0; c < 3; ++c) {
          const double fd = (tp.angle[c] - tm.angle[c]) / (2 * h);
          EXPECT_NEAR(t.d_angle_d_length[c][e], fd, 1e-6 * std::max(1.0, std::abs(fd)));
        }
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 200);
}

TEST(Geometry, InvalidTrianglesAreRejected) {
  for (Geometry g : kGeometries) {
    EXPECT_FALSE(corner_angles(g, {1.0, 0.4, 0.5}).valid) << to_string(g);
    EXPECT_FALSE(corner_angles(g, {0.0, 0.4, 0.5}).valid) << to_string(g);
  }
  EXPECT_FALSE(is_valid_triangle(Geometry::Spherical, {2.2, 2.2, 2.2}));  // perimeter > 2 pi
  EXPECT_TRUE(is_valid_triangle(Geometry::Hyperbolic, {2.2, 2.2, 2.2}));
}

// The apex of a triangle on its base: at its two distances, above the base, and a needle's height
// to its own precision: the apex 1e-9 above the base's end (sides 1, 1 and 1e-9, the distance to
// the far end 1 to within rounding; the cosine law's height sqrt(b^2 - x^2) is 0 there).
TEST(Geometry, TriangleApexKeepsANeedlesHeight) {
  const auto apex = triangle_apex(5, 3, 4);  // the 3-4-5 triangle, right angle at the apex
  EXPECT_NEAR(apex[0], 1.8, 1e-15);
  EXPECT_NEAR(apex[1], 2.4, 1e-15);
  const auto needle = triangle_apex(1.0, 1.0, 1e-9);
  EXPECT_NEAR(needle[0], 1.0, 1e-15);
  EXPECT_NEAR(needle[1] / 1e-9, 1.0, 1e-6);
  // Lengths that do not close (by rounding): on the base's line where the cosine law puts it.
  const auto flat = triangle_apex(1.0, 0.3, 0.6);
  EXPECT_EQ(flat[1], 0.0);
  EXPECT_NEAR(flat[0], (0.09 + 1 - 0.36) / 2, 1e-15);
}

TEST(Geometry, AreaMatchesGaussBonnetForOneTriangle) {
  // Small triangles: H2 and S2 areas approach the Euclidean one.
  const std::array<double, 3> l = {0.01, 0.012, 0.015};
  const double e2 =
      triangle_area(Geometry::Euclidean, l, corner_angles(Geometry::Euclidean, l).angle);
  const double h2 =
      triangle_area(Geometry::Hyperbolic, l, corner_angles(Geometry::Hyperbolic, l).angle);
  const double s2 =
      triangle_area(Geometry::Spherical, l, corner_angles(Geometry::Spherical, l).angle);
  EXPECT_NEAR(h2 / e2, 1.0, 1e-3);
  EXPECT_NEAR(s2 / e2, 1.0, 1e-3);
}

}  // namespace
}  // namespace ricci
