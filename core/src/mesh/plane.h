// The plane's cross product, for the orientation tests of layouts and overlays, and the
// quasi-conformal ratio of a linear map of the plane (not installed API).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace ricci::detail {

//! a.x b.y - a.y b.x: twice the signed area of the triangle (0, a, b), positive when counter-
//! clockwise.
inline double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

//! The quasi-conformal ratio of the linear map j (its larger singular value over its smaller) whose
//! determinant is `det`, given apart (the ratio of two areas, exact in sign where computed from
//! the triangles rather than from j's entries, which a needle's inverse inflates): j is the sum of
//! a similarity and an anticonformal map of scales alpha and beta, its singular values alpha +
//! beta and |alpha - beta|, whose product is |det|. At least 1; infinite where not finite.
//! (sqrt, not std::hypot: glibc 2.35's hypot symbol would keep the wheel from manylinux_2_34.)
inline double singular_value_ratio(const Eigen::Matrix2d& j, double det) {
  const double p = j(0, 0) + j(1, 1), q = j(1, 0) - j(0, 1);
  const double r = j(0, 0) - j(1, 1), t = j(1, 0) + j(0, 1);
  const double alpha = 0.5 * std::sqrt(p * p + q * q), beta = 0.5 * std::sqrt(r * r + t * t);
  const double ratio = (alpha + beta) * (alpha + beta) / std::abs(det);
  if (ratio < 1) return 1.0;                                            // rounding's
  return ratio >= 1 ? ratio : std::numeric_limits<double>::infinity();  // NaN: a map overflowed
}

}  // namespace ricci::detail
