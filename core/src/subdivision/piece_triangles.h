// The triangles a piece of the common subdivision is delivered as.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "ricci/subdivision/subdivided_mesh.h"

namespace ricci::detail {

// Triangles of a convex polygon given by its corners in order in two planar pictures: the domain
// (the polygon in its input face) and its image (in the layout). NearestToConformal: of the
// triangulations with no triangle flat or turned over in either picture, the one of the least sum
// over its triangles of (log K)^2, K the quasi-conformal ratio of the triangle's map from the
// domain to the image (dynamic programming over the polygon's diagonals). Roundest, or where
// every triangulation has a flat or turned triangle: ears cut off the domain at its strictly convex
// corners, the roundest first (none flat where sides hold several points in a row).
std::vector<std::array<size_t, 3>> piece_triangles(const std::vector<Eigen::Vector2d>& domain,
                                                   const std::vector<Eigen::Vector2d>& image,
                                                   PieceTriangles how);

// The quasi-conformal ratio (larger singular value over smaller) of the affine map taking triangle
// a to triangle b; infinite where either is flat or the map turns it over.
double quasi_conformal_ratio(const std::array<Eigen::Vector2d, 3>& a,
                             const std::array<Eigen::Vector2d, 3>& b);

}  // namespace ricci::detail
