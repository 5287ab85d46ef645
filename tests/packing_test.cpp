// Packing: every chart inside [0, 1]^2 at one common scale, turned by a rotation only, no two
// charts closer than the padding, and a fair share of the square used.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include "ricci/layout/packing.h"

#include "ricci/mesh/errors.h"
#include "ricci/mesh/geometry.h"

namespace ricci::test {
namespace {

using Triangle = std::array<Eigen::Vector2d, 3>;
using Chart = std::vector<Triangle>;

// A w x h rectangle (two triangles), turned by `angle` and moved.
Chart rectangle(double w, double h, double angle, Eigen::Vector2d at) {
  const Eigen::Matrix2d r = Eigen::Rotation2D<double>(angle).toRotationMatrix();
  const auto p = [&](double x, double y) {
    return Eigen::Vector2d(r * Eigen::Vector2d(x, y) + at);
  };
  return {{p(0, 0), p(w, 0), p(w, h)}, {p(0, 0), p(w, h), p(0, h)}};
}

// An L of two rectangles.
Chart ell(double s, Eigen::Vector2d at) {
  Chart a = rectangle(3 * s, s, 0, at), b = rectangle(s, 2 * s, 0, at + Eigen::Vector2d(0, s));
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

double distance_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                           const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * d)).norm();
}

// Smallest distance between two charts' triangles (corners to sides; they do not overlap then).
double gap(const Chart& a, const Chart& b) {
  double g = INFINITY;
  for (const Chart* x : {&a, &b}) {
    const Chart& y = x == &a ? b : a;
    for (const Triangle& s : *x) {
      for (const Triangle& t : y) {
        for (const auto& p : s) {
          for (int i = 0; i < 3; ++i) g = std::min(g, distance_to_segment(p, t[i], t[(i + 1) % 3]));
        }
      }
    }
  }
  return g;
}

// Chart k as packed, every corner checked to lie in [0, 1]^2.
Chart placed(const Packing& p, size_t k, const Chart& chart) {
  Chart c;
  for (const Triangle& t : chart) {
    Triangle u;
    for (int i = 0; i < 3; ++i) {
      u[i] = p.scale * p.rotation[k] * t[i] + p.offset[k];
      EXPECT_GE(u[i].minCoeff(), 0);
      EXPECT_LE(u[i].maxCoeff(), 1);
    }
    c.push_back(u);
  }
  return c;
}

// Every two packed charts at least the padding apart, in the texture's texels.
void expect_apart(const std::vector<Chart>& packed, const PackingOptions& o) {
  for (size_t a = 0; a < packed.size(); ++a) {
    for (size_t b = a + 1; b < packed.size(); ++b) {
      EXPECT_GE(gap(packed[a], packed[b]), o.padding / double(o.texture_size) * (1 - 1e-9))
          << a << " " << b;
    }
  }
}

TEST(Packing, ChartsLandInTheSquareAtOneScaleApartByThePadding) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> size(0.2, 2), angle(0, 2 * kPi);
  std::vector<Chart> charts;
  for (int k = 0; k < 24; ++k) {
    charts.push_back(k % 3 ? rectangle(size(random), size(random), angle(random), {5.0 * k, 0})
                           : ell(size(random) / 2, {-5.0 * k, 3}));
  }
  PackingOptions o;
  o.texture_size = 512;
  o.padding = 4;
  const Packing p = pack_charts(charts, o);
  std::vector<Chart> packed;
  double area = 0;
  for (size_t k = 0; k < charts.size(); ++k) {
    // A rotation: orthogonal with determinant +1.
    EXPECT_LT((p.rotation[k].transpose() * p.rotation[k] - Eigen::Matrix2d::Identity()).norm(),
              1e-12);
    EXPECT_NEAR(p.rotation[k].determinant(), 1, 1e-12);
    packed.push_back(placed(p, k, charts[k]));
    for (const Triangle& u : packed.back()) {
      const Eigen::Vector2d a = u[1] - u[0], b = u[2] - u[0];
      area += 0.5 * (a.x() * b.y() - a.y() * b.x());
    }
  }
  EXPECT_NEAR(area, p.utilization, 1e-12);
  EXPECT_GT(p.utilization, 0.4);
  EXPECT_EQ(p.padding, o.padding);
  expect_apart(packed, o);
}

// A star of `points` spikes as a fan of thin triangles around the origin, turned and moved: rows
// of the rasters cross many triangles, most of them wider than a cell and slanted.
Chart star(int points, double inner, double outer, double angle, Eigen::Vector2d at) {
  const Eigen::Matrix2d r = Eigen::Rotation2D<double>(angle).toRotationMatrix();
  std::vector<Eigen::Vector2d> rim;
  for (int i = 0; i < 2 * points; ++i) {
    const double a = kPi * i / points, radius = i % 2 ? inner : outer;
    rim.emplace_back(r * Eigen::Vector2d(radius * std::cos(a), radius * std::sin(a)) + at);
  }
  Chart chart;
  for (size_t i = 0; i < rim.size(); ++i) chart.push_back({at, rim[i], rim[(i + 1) % rim.size()]});
  return chart;
}

TEST(Packing, ChartsOfThinSlantedTrianglesKeepThePadding) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> size(0.3, 1.5), angle(0, 2 * kPi);
  std::vector<Chart> charts;
  for (int k = 0; k < 16; ++k) {
    const double outer = size(random);
    charts.push_back(star(5 + k % 7, 0.3 * outer, outer, angle(random), {3.0 * k, -2.0 * k}));
  }
  PackingOptions o;
  o.texture_size = 256;
  o.padding = 3;
  const Packing p = pack_charts(charts, o);
  std::vector<Chart> packed;
  for (size_t k = 0; k < charts.size(); ++k) packed.push_back(placed(p, k, charts[k]));
  EXPECT_EQ(p.padding, o.padding);
  expect_apart(packed, o);
}

TEST(Packing, SeveralChartsSpanTheSquareWithinHalfThePadding) {
  // The rasters' cells round each chart's box up: the square is the charts' own box, half the
  // padding from its sides, the longer of its sides spanning it (not a cell or two short).
  std::mt19937 random(5);
  std::uniform_real_distribution<double> size(0.2, 2), angle(0, 2 * kPi);
  for (int count : {3, 10, 40}) {
    std::vector<Chart> charts;
    for (int k = 0; k < count; ++k) {
      charts.push_back(rectangle(size(random), size(random), angle(random), {4.0 * k, 0}));
    }
    PackingOptions o;
    o.texture_size = 512;
    o.padding = 6;
    const Packing p = pack_charts(charts, o);
    const double half = 0.5 * o.padding / o.texture_size;
    Eigen::AlignedBox2d box;
    for (size_t k = 0; k < charts.size(); ++k) {
      for (const Triangle& u : placed(p, k, charts[k])) {
        for (const auto& q : u) box.extend(q);
      }
    }
    EXPECT_NEAR(box.min().x(), half, 1e-12) << count;
    EXPECT_NEAR(box.min().y(), half, 1e-12) << count;
    EXPECT_NEAR(box.max().maxCoeff(), 1 - half, 1e-12) << count;
    EXPECT_EQ(p.padding, o.padding) << count;
  }
}

TEST(Packing, APackingAgainForTheMarginSaysThePaddingItMeets) {
  // Few charts: the first guess of the extent is far off, the margin is packed again, and the
  // padding said is the last packing's, which meets the padding asked.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> size(0.3, 3);
  for (int count : {2, 3, 5, 8, 12}) {
    std::vector<Chart> charts;
    for (int k = 0; k < count; ++k) {
      charts.push_back(rectangle(size(random), size(random), 0.3 * k, {10.0 * k, 0}));
    }
    const Packing p = pack_charts(charts);
    EXPECT_EQ(p.padding, PackingOptions().padding) << count;
    std::vector<Chart> packed;
    for (size_t k = 0; k < charts.size(); ++k) packed.push_back(placed(p, k, charts[k]));
    expect_apart(packed, PackingOptions());
  }
}

TEST(Packing, ALongChartIsTurnedToItsSmallestBox) {
  // A 10 x 1 strip at 30 degrees: packed alone, its box is upright (its long side on an axis).
  const Packing p = pack_charts(std::vector<Chart>{rectangle(10, 1, kPi / 6, {0, 0})});
  const Eigen::Vector2d axis =
      p.rotation[0] * Eigen::Vector2d(std::cos(kPi / 6), std::sin(kPi / 6));
  EXPECT_NEAR(std::abs(axis.x()) * std::abs(axis.y()), 0, 1e-12);
}

TEST(Packing, OneChartSpansTheSquareWithinHalfThePadding) {
  // Packed alone, a 3 x 1 strip at 20 degrees: its upright box spans the square's width, half
  // the padding from its sides, and its height, a third of that, fits.
  PackingOptions o;
  o.texture_size = 256;
  o.padding = 8;
  const Chart chart = rectangle(3, 1, kPi / 9, {2, -1});
  const Packing p = pack_charts(std::vector<Chart>{chart}, o);
  const double half = 0.5 * o.padding / o.texture_size;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(INFINITY), hi = -lo;
  double area = 0;
  for (const Triangle& t : chart) {
    Triangle u;
    for (int i = 0; i < 3; ++i) {
      u[i] = p.scale * p.rotation[0] * t[i] + p.offset[0];
      lo = lo.cwiseMin(u[i]), hi = hi.cwiseMax(u[i]);
    }
    const Eigen::Vector2d a = u[1] - u[0], b = u[2] - u[0];
    area += 0.5 * (a.x() * b.y() - a.y() * b.x());
  }
  EXPECT_NEAR(lo.x(), half, 1e-12);
  EXPECT_NEAR(lo.y(), half, 1e-12);
  EXPECT_NEAR(std::max(hi.x(), hi.y()), 1 - half, 1e-12);
  EXPECT_NEAR(std::min(hi.x(), hi.y()), half + (1 - 2 * half) / 3, 1e-12);
  EXPECT_NEAR(area, p.utilization, 1e-12);
}

TEST(Packing, ChartsTooManyForTheTextureAtThePaddingAreSaidToBeNearer) {
  // 100 unit squares in a texture of 32 texels: 10 to a side with 4 texels between them would
  // take 40. The packing says how far apart they are, and they are at least that far.
  std::vector<Chart> charts;
  for (int k = 0; k < 100; ++k) charts.push_back(rectangle(1, 1, 0.1 * k, {3.0 * k, 0}));
  PackingOptions o;
  o.texture_size = 32;
  o.padding = 4;
  const Packing p = pack_charts(charts, o);
  EXPECT_LT(p.padding, o.padding);
  EXPECT_GT(p.padding, 0.5 * o.padding);
  std::vector<Chart> packed;
  std::vector<Eigen::AlignedBox2d> box;
  for (size_t k = 0; k < charts.size(); ++k) {
    packed.push_back(placed(p, k, charts[k]));
    box.emplace_back();
    for (const Triangle& u : packed.back()) {
      for (const auto& q : u) box.back().extend(q);
    }
  }
  double nearest = INFINITY;
  for (size_t a = 0; a < packed.size(); ++a) {
    for (size_t b = a + 1; b < packed.size(); ++b) {
      if (box[a].exteriorDistance(box[b]) * o.texture_size > o.padding) continue;
      nearest = std::min(nearest, gap(packed[a], packed[b]) * o.texture_size);
    }
  }
  EXPECT_GE(nearest, p.padding * (1 - 1e-9));
}

TEST(Packing, OptionsOutOfRangeAreRefused) {
  PackingOptions o;
  o.texture_size = 8;
  EXPECT_THROW(pack_charts(std::vector<Chart>{rectangle(1, 1, 0, {0, 0})}, o),
               InvalidArgumentError);
}

}  // namespace
}  // namespace ricci::test
