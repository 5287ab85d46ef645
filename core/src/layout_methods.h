// The two layout methods behind lay_out() and what they share (not installed API).
#pragma once

#include <array>
#include <vector>

#include "ricci/layout.h"

namespace ricci::detail {

//! Corner angles of every face, checked. \throws InvalidArgumentError naming the first face that
//! is not a valid triangle of the geometry.
std::vector<std::array<double, 3>> face_angles(const Triangulation& mesh, Geometry geometry,
                                               const std::vector<double>& lengths);

//! Corner of face f that holds vertex v, or -1.
int corner_of(const Triangulation& mesh, int f, int v);

//! The largest relative error in an edge's length that a developed plane layout may have before
//! plane_layout fits the edge vectors by least squares instead.
inline constexpr double kDevelopedLengthError = 1e-8;

//! E2, every topology: developed face by face, each wedge (a vertex's fan of faces on one side of
//! the cut) at the mean of its corners; where an edge's length is then off by more than
//! kDevelopedLengthError, least squares over the edge vectors with one unknown per wedge.
Layout plane_layout(const Triangulation& mesh, const std::vector<double>& lengths,
                    LinearSolverKind solver, double max_developed_error = kDevelopedLengthError);

//! Any geometry: triangle by triangle; H2 from a central face with a cut of shortest paths from it,
//! otherwise from the face deepest inside the cut disk. Sets the cut and the corners only: the
//! caller glues them (glue_along_cut) once its corners are final. H2 charts: of `chart_radius`.
Layout develop(const Triangulation& mesh, Geometry geometry, const std::vector<double>& lengths,
               double chart_radius = kChartRadius);

//! The Poincare disk layout draws a triangle's sides straight in the disk's coordinates: the point
//! z of the geodesic from p to q goes where it projects onto the segment p-q (the arc is less than
//! a half circle, so the order along the side is kept).
Eigen::Vector3d onto_drawn_side(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                const Eigen::Vector3d& z);

//! The point of the geodesic from p to q in the Poincare disk whose hyperboloid vector is
//! (1 - t) P + t Q, normalized (P, Q: the hyperboloid vectors of p and q): t = 1/2 is the
//! geodesic's midpoint.
Eigen::Vector3d disk_geodesic_point(const Eigen::Vector3d& p, const Eigen::Vector3d& q, double t);

//! Fills the deck transformations (E2, H2), the closure error and the flipped-face count of a
//! layout whose corners and cut are set.
void glue_along_cut(const Triangulation& mesh, Layout& layout);

}  // namespace ricci::detail
