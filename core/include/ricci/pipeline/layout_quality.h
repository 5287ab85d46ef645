// How good a layout is, measured against the input mesh: the numbers the tool's report and the
// plugin's log give.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/flow_result.h"
#include "ricci/mesh/compact_mesh.h"

namespace ricci {

struct LayoutQuality {
  double max_curvature_error = 0;   //!< max |K - Kbar| over vertices with a target
  double mean_curvature_error = 0;  //!< mean |K - Kbar| over them
  //! Quasi-conformal ratio sigma_max / sigma_min of the affine map from each input triangle to
  //! its layout triangle (1 = angles kept): median, 95th percentile, max over faces.
  double quasi_conformal_median = 1, quasi_conformal_p95 = 1, quasi_conformal_max = 1;
  //! Area ratio per face, (layout area / total) / (input area / total): 5th percentile, median,
  //! 95th percentile.
  double area_ratio_p5 = 1, area_ratio_median = 1, area_ratio_p95 = 1;
  //! Faces whose layout triangle is turned over or degenerate (with an orientation the corners
  //! determine: beyond their rounding).
  int flipped_faces = 0;
  int first_flipped_face = -1;
  //! Faces whose layout triangle keeps its orientation but has less than 1e-12 of the layout's
  //! mean triangle area (squeezed below what float texture coordinates resolve), or is so small
  //! that its corners' rounding decides its orientation.
  int collapsed_faces = 0;
  int first_collapsed_face = -1;
};

//! The q-quantile of x (0 <= q <= 1) as the reports give it: the element of rank floor(q n), at
//! most the largest; 1 where x is empty.
double quantile(std::vector<double> x, double q);

//! A triangle whose orientation its double-precision corners do not determine: |orientation|
//! within what rounding the corners (each off by about 2^-52 of its magnitude, allowed 64 times
//! that) can make of it. Such a face is degenerate in double precision (counted as collapsed),
//! not turned.
bool orientation_unresolved(const std::array<Eigen::Vector3d, 3>& corners);

//! Measures a layout given per input face and corner: points in the plane (z = 0), in the
//! Poincare disk (z = 0, measured in its Euclidean coordinates, as a texture shows them), or on
//! the unit sphere (chords; orientation against the outward normal).
LayoutQuality measure_layout(const CompactMesh& mesh, Geometry geometry, const FlowResult& result,
                             const std::vector<std::array<Eigen::Vector3d, 3>>& corners);

//! The same for any triangle mesh: per face its input side lengths (l[k] opposite corner k).
LayoutQuality measure_layout(const std::vector<std::array<double, 3>>& input_sides,
                             Geometry geometry, const FlowResult& result,
                             const std::vector<std::array<Eigen::Vector3d, 3>>& corners);

//! Side lengths (l[k] opposite corner k) of every face of a mesh in 3D.
std::vector<std::array<double, 3>> face_sides(const std::vector<Eigen::Vector3d>& positions,
                                              const std::vector<std::array<int, 3>>& faces);

}  // namespace ricci
