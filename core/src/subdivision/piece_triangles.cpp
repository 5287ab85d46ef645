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

// A triangle rounder than this in both pictures is neither flat nor, to rounding, turned over.
constexpr double kFlat = 1e-12;

// Twice the signed area over the sum of the squared sides: 1 / (2 sqrt 3) at most (equilateral).
double roundness(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
  const double scale = (q - p).squaredNorm() + (r - q).squaredNorm() + (p - r).squaredNorm();
  return scale > 0 ? cross(q - p, r - p) / scale : 0;
}

// Ears cut off at corners strictly convex in the domain, the roundest first, none whose cut
// leaves the other corners on a line (where sides hold several points in a row, the last three
// left could be flat).
std::vector<std::array<size_t, 3>> roundest_ears(const std::vector<Eigen::Vector2d>& domain) {
  std::vector<size_t> left(domain.size());
  for (size_t i = 0; i < left.size(); ++i) left[i] = i;
  // Whether the corners left but the one at `skip` enclose area.
  auto encloses = [&](size_t skip) {
    const size_t n = left.size();
    double area = 0, scale = 0;
    const Eigen::Vector2d& o = domain[left[skip == 0 ? 1 : 0]];
    for (size_t i = 0; i < n; ++i) {
      const size_t j = (i + 1) % n == skip ? (i + 2) % n : (i + 1) % n;
      if (i == skip) continue;
      area += cross(domain[left[i]] - o, domain[left[j]] - o);
      scale += (domain[left[j]] - domain[left[i]]).squaredNorm();
    }
    return area > kFlat * scale;
  };
  std::vector<std::array<size_t, 3>> out;
  while (left.size() > 3) {
    const size_t n = left.size();
    size_t best = n;
    double best_roundness = 0;
    for (size_t i = 0; i < n; ++i) {
      const double r =
          roundness(domain[left[(i + n - 1) % n]], domain[left[i]], domain[left[(i + 1) % n]]);
      if (r > best_roundness && encloses(i)) best = i, best_roundness = r;
    }
    if (best == n) best = 0;  // no ear both round and leaving area: the polygon has none
    out.push_back({left[(best + n - 1) % n], left[best], left[(best + 1) % n]});
    left.erase(left.begin() + static_cast<long>(best));
  }
  out.push_back({left[0], left[1], left[2]});
  return out;
}

// The triangulation of the least sum of (log K)^2 (dynamic programming over the diagonals), or
// none where each has a triangle flat or turned over in either picture.
std::vector<std::array<size_t, 3>> nearest_to_conformal(const std::vector<Eigen::Vector2d>& domain,
                                                        const std::vector<Eigen::Vector2d>& image) {
  const size_t n = domain.size();
  // least[i n + j]: the least sum over the polygon i, i + 1, ..., j closed by the diagonal (i, j);
  // apex[i n + j] the third corner of its triangle on that diagonal.
  std::vector<double> least(n * n, 0.0);
  std::vector<size_t> apex(n * n, 0);
  for (size_t width = 2; width < n; ++width) {
    for (size_t i = 0; i + width < n; ++i) {
      const size_t j = i + width;
      double best = kInfinity;
      for (size_t k = i + 1; k < j; ++k) {
        const double sides = least[i * n + k] + least[k * n + j];
        if (!(sides < best)) continue;
        const double K = std::log(quasi_conformal_ratio({domain[i], domain[k], domain[j]},
                                                        {image[i], image[k], image[j]}));
        if (sides + K * K < best) best = sides + K * K, apex[i * n + j] = k;
      }
      least[i * n + j] = best;
    }
  }
  if (!(least[n - 1] < kInfinity)) return {};
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

}  // namespace

double quasi_conformal_ratio(const std::array<Eigen::Vector2d, 3>& a,
                             const std::array<Eigen::Vector2d, 3>& b) {
  if (roundness(a[0], a[1], a[2]) <= kFlat || roundness(b[0], b[1], b[2]) <= kFlat)
    return kInfinity;
  Eigen::Matrix2d A, B;
  A << a[1] - a[0], a[2] - a[0];
  B << b[1] - b[0], b[2] - b[0];
  // det J, the ratio of the areas, positive (neither triangle flat nor turned, above).
  return singular_value_ratio(B * A.inverse(),
                              cross(b[1] - b[0], b[2] - b[0]) / cross(a[1] - a[0], a[2] - a[0]));
}

std::vector<std::array<size_t, 3>> piece_triangles(const std::vector<Eigen::Vector2d>& domain,
                                                   const std::vector<Eigen::Vector2d>& image,
                                                   PieceTriangles how) {
  if (domain.size() < 3 || image.size() != domain.size()) return {};
  if (domain.size() == 3) return {{0, 1, 2}};  // most pieces: nothing to choose
  if (how == PieceTriangles::NearestToConformal) {
    std::vector<std::array<size_t, 3>> out = nearest_to_conformal(domain, image);
    if (!out.empty()) return out;
  }
  return roundest_ears(domain);
}

}  // namespace ricci::detail
