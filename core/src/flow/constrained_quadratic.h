// The least of a convex quadratic under linear inequalities (and the sum of the variables fixed,
// or not): the cone placement's curvatures of least distortion (flow/cone_placement.cpp).
#pragma once

#include <Eigen/Core>

namespace ricci {

struct ConstrainedQuadratic {
  //! f(x) = x^T q x / 2 + b^T x, q symmetric and positive definite (on the planes sum x = const
  //! where `sum_fixed`).
  Eigen::MatrixXd q;
  Eigen::VectorXd b;
  //! The constraints a x <= limit, a row each.
  Eigen::MatrixXd a;
  Eigen::VectorXd limit;
  bool sum_fixed = false;  //!< sum x stays that of the start
};

//! The minimizer of a ConstrainedQuadratic, by a primal active set from `start`, which must meet
//! the constraints: each step solves the problem with the constraints of its working set as
//! equalities, stops at the first other constraint it meets and adds it, or where it stays,
//! drops the constraint whose multiplier is most negative. Costs O((n + working set)^3) a step;
//! f never rises from the start's, and the start is returned where a step's system is singular or
//! the result would break a constraint by more than rounding (a degenerate working set).
Eigen::VectorXd minimize_constrained(const ConstrainedQuadratic& p, const Eigen::VectorXd& start);

}  // namespace ricci
