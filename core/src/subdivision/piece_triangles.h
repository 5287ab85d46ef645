// The triangles a piece of the common subdivision is delivered as.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace ricci::detail {

// Triangles of a convex polygon given by its corners in order in two planar pictures: the domain
// (the polygon in its input face) and its image (in the layout). The map between the pictures is
// drawn piecewise linear on them, so their choice decides how near to conformal the drawing is:
// of the triangulations with no triangle flat or turned over in either picture, the one whose
// triangles' quasi-conformal ratios K have the least sum of (log K)^2 (dynamic programming over
// the polygon's diagonals). Empty when every triangulation has a flat or turned triangle.
std::vector<std::array<size_t, 3>> conformal_triangles(const std::vector<Eigen::Vector2d>& domain,
                                                       const std::vector<Eigen::Vector2d>& image);

// The quasi-conformal ratio (larger singular value over smaller) of the affine map taking triangle
// a to triangle b; infinite where either is flat or the map turns it over.
double quasi_conformal_ratio(const std::array<Eigen::Vector2d, 3>& a,
                             const std::array<Eigen::Vector2d, 3>& b);

}  // namespace ricci::detail
