// What the layout methods share: a face's corner angles and corners, and the Poincare disk's
// drawn sides (not installed API).
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/geometry.h"
#include "ricci/mesh/triangulation.h"

namespace ricci::detail {

//! Corner angles of every face, checked. \throws InvalidArgumentError naming the first face that
//! is not a valid triangle of the geometry.
std::vector<std::array<double, 3>> face_angles(const Triangulation& mesh, Geometry geometry,
                                               const std::vector<double>& lengths);

//! Corner of face f that holds vertex v, or -1.
int corner_of(const Triangulation& mesh, int f, int v);

//! The Poincare disk layout draws a triangle's sides straight in the disk's coordinates: the point
//! z of the geodesic from p to q goes where it projects onto the segment p-q (the arc is less than
//! a half circle, so the order along the side is kept).
Eigen::Vector3d onto_drawn_side(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                const Eigen::Vector3d& z);

//! The point of the geodesic from p to q in the Poincare disk whose hyperboloid vector is
//! (1 - t) P + t Q, normalized (P, Q: the hyperboloid vectors of p and q): t = 1/2 is the
//! geodesic's midpoint.
Eigen::Vector3d disk_geodesic_point(const Eigen::Vector3d& p, const Eigen::Vector3d& q, double t);

}  // namespace ricci::detail
