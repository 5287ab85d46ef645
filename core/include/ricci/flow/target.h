// Target curvature Kbar and the vertices whose conformal factor is held fixed instead.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/compact_mesh.h"
#include "ricci/mesh/geometry.h"

namespace ricci {

struct TargetCurvature {
  //! Kbar per vertex; ignored (and reported as NaN) where the vertex is fixed.
  Eigen::VectorXd curvature;
  //! Per vertex: 1 where u keeps its initial value instead of reaching a curvature.
  std::vector<char> fixed;

  bool is_fixed(int v) const { return fixed[v] != 0; }
  int num_fixed() const;
  //! Kbar per vertex with NaN where u is fixed: the inverse of from_values.
  Eigen::VectorXd values() const;

  //! Kbar = 0 at every vertex (closed surfaces: flat torus, hyperbolic metric, round sphere).
  static TargetCurvature zero(const CompactMesh& mesh);
  //! u fixed on the boundary (boundary lengths kept, where no flip crosses it), Kbar = 0 inside:
  //! least area distortion.
  static TargetCurvature free_boundary(const CompactMesh& mesh);
  //! Explicit Kbar per vertex; NaN entries mean "u fixed at this vertex".
  static TargetCurvature from_values(const CompactMesh& mesh, const Eigen::VectorXd& values);
  //! free_boundary on surfaces with boundary, zero on closed ones (the uniformization presets,
  //! such as the unit disk, are in presets.h).
  static TargetCurvature free_boundary_or_zero(const CompactMesh& mesh);
};

//! Checks that a solution can exist: sizes, finite values, Kbar < 2 pi inside and < pi on the
//! boundary, and, when every vertex has a curvature target, discrete Gauss-Bonnet
//! sum Kbar + kappa A = 2 pi chi with a positive area A in H2 and S2.
//! \throws InvalidTargetError naming the violated condition and what to change.
void check_target(const CompactMesh& mesh, Geometry geometry, const TargetCurvature& target);

//! The area Gauss-Bonnet asks of the result: |2 pi chi - sum Kbar| in H2 and S2 when every
//! vertex has a curvature target, 0 when the area is not determined (E2, or fixed vertices).
double gauss_bonnet_area(const CompactMesh& mesh, Geometry geometry, const TargetCurvature& target);

}  // namespace ricci
