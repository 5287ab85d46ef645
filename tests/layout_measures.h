// Measures of a delivered map, written on the test side, apart from the library's own
// (ricci/mesh/geometry.h): the tests check the library's layouts with them.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

namespace ricci::test {

//! The quasi-conformal ratio of the affine map between two triangles of R^3 (a layout's in the
//! plane z = 0, a chord triangle of the sphere, ...): the ratio of its singular values, each
//! triangle in a frame of its own plane. 1 for a similarity; infinite or NaN where one of them
//! has no area.
double quasi_conformal(const std::array<Eigen::Vector3d, 3>& from,
                       const std::array<Eigen::Vector3d, 3>& to);

//! The p-quantile of x (0 <= p <= 1), interpolated linearly between order statistics.
double percentile(std::vector<double> x, double p);

}  // namespace ricci::test
