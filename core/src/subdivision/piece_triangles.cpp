#include "subdivision/piece_triangles.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/LU>

#include "mesh/plane.h"

namespace ricci::detail {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Twice the signed area over the sum of the squared sides: 2 / sqrt(3) at most (equilateral).
double roundness(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
  const double scale = (q - p).squaredNorm() + (r - q).squaredNorm() + (p - r).squaredNorm();
  return scale > 0 ? cross(q - p, r - p) / scale : 0;
}

// A triangle rounder than this in both pictures is neither flat nor, to rounding, turned over.
constexpr double kFlat = 1e-12;

}  // namespace

double quasi_conformal_ratio(const std::array<Eigen::Vector2d, 3>& a,
                             const std::array<Eigen::Vector2d, 3>& b) {
  if (roundness(a[0], a[1], a[2]) <= kFlat || roundness(b[0], b[1], b[2]) <= kFlat)
    return kInfinity;
  Eigen::Matrix2d A, B;
  A << a[1] - a[0], a[2] - a[0];
  B << b[1] - b[0], b[2] - b[0];
  const Eigen::Matrix2d J = B * A.inverse();
  const double s = J.squaredNorm(), d = J.determinant();
  // The singular values' squares sum to s and multiply to d^2.
  return (s + std::sqrt(std::max(0.0, s * s - 4 * d * d))) / (2 * d);
}

std::vector<std::array<size_t, 3>> conformal_triangles(const std::vector<Eigen::Vector2d>& domain,
                                                       const std::vector<Eigen::Vector2d>& image) {
  const size_t n = domain.size();
  if (n < 3 || image.size() != n) return {};
  // cost[i][j]: the least sum over the polygon i, i + 1, ..., j cut off by diagonal (i, j);
  // apex[i][j] the third corner of its triangle on that diagonal.
  std::vector<double> cost(n * n, 0.0);
  std::vector<size_t> apex(n * n, 0);
  for (size_t width = 2; width < n; ++width) {
    for (size_t i = 0; i + width < n; ++i) {
      const size_t j = i + width;
      double best = kInfinity;
      for (size_t k = i + 1; k < j; ++k) {
        const double sides = cost[i * n + k] + cost[k * n + j];
        if (!(sides < best)) continue;
        const double K = quasi_conformal_ratio({domain[i], domain[k], domain[j]},
                                               {image[i], image[k], image[j]});
        const double total = sides + std::log(K) * std::log(K);
        if (total < best) best = total, apex[i * n + j] = k;
      }
      cost[i * n + j] = best;
    }
  }
  if (!(cost[n - 1] < kInfinity)) return {};
  std::vector<std::array<size_t, 3>> out;
  std::vector<std::pair<size_t, size_t>> todo = {{0, n - 1}};
  while (!todo.empty()) {
    const auto [i, j] = todo.back();
    todo.pop_back();
    if (j - i < 2) continue;
    const size_t k = apex[i * n + j];
    out.push_back({i, k, j});
    todo.push_back({i, k});
    todo.push_back({k, j});
  }
  return out;
}

}  // namespace ricci::detail
