// What the layout methods share: a face's corner angles and corners, the Poincare disk's geodesic
// points, one position per copy of a vertex (not installed API).
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

//! Gives every copy of a vertex one position: corners of one vertex within 1e-13 of the layout's
//! extent of each other are one copy of it (across a cut the copies lie far apart), set to the
//! copy's first corner. Corners computed face by face differ in their last bits, and thin faces
//! turn that into angle errors of 1e-8 at the vertex. Copies farther apart are the development's
//! drift (a final side's two faces developed along different paths), and stay: snapped together,
//! they turned thin faces by the gap over their width (cura-zav-maxpro.stl at 1e-10: angle sums
//! off by 2.6e-7 at copies 1e-10 apart, 2.2e-10 at 1e-13; occt-tr12j.stl 6.8e-9 and 1.4e-10).
void weld_corner_copies(const std::vector<std::array<int, 3>>& faces,
                        std::vector<std::array<Eigen::Vector3d, 3>>& corners);

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
