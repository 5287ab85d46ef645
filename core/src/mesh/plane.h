// The plane's cross product, for the orientation tests of layouts and overlays (not installed
// API).
#pragma once

#include <Eigen/Core>

namespace ricci::detail {

//! a.x b.y - a.y b.x: twice the signed area of the triangle (0, a, b), positive when counter-
//! clockwise.
inline double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

}  // namespace ricci::detail
