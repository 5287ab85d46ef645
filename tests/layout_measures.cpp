#include "layout_measures.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <limits>

namespace ricci::test {

namespace {

// The triangle's sides from its first corner, in an orthonormal frame of its plane.
Eigen::Matrix2d in_own_plane(const std::array<Eigen::Vector3d, 3>& t) {
  const Eigen::Vector3d e1 = t[1] - t[0], e2 = t[2] - t[0];
  const Eigen::Vector3d x = e1.normalized(), y = e1.cross(e2).cross(e1).normalized();
  Eigen::Matrix2d m;
  m << e1.dot(x), e2.dot(x), e1.dot(y), e2.dot(y);
  return m;
}

}  // namespace

double quasi_conformal(const std::array<Eigen::Vector3d, 3>& from,
                       const std::array<Eigen::Vector3d, 3>& to) {
  const Eigen::Vector2d s =
      Eigen::JacobiSVD<Eigen::Matrix2d>(in_own_plane(to) * in_own_plane(from).inverse())
          .singularValues();
  return s[1] > 0 ? s[0] / s[1] : std::numeric_limits<double>::infinity();
}

double percentile(std::vector<double> x, double p) {
  std::sort(x.begin(), x.end());
  const double at = p * static_cast<double>(x.size() - 1);
  const size_t i = static_cast<size_t>(at);
  return i + 1 < x.size() ? x[i] + (at - static_cast<double>(i)) * (x[i + 1] - x[i]) : x[i];
}

}  // namespace ricci::test
