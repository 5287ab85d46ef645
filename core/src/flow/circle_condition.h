// Boundary loops on circles: the boundary curvature that makes a flat metric's boundary loops
// chords of circles, as a function of the boundary lengths, and its derivative in u for the
// Euclidean Yamabe flow, so that one solve reaches a circle domain (ricci_flow.h,
// RicciFlowSolver::solve_circle_domain). Not installed API.
//
// Loop c with edges e (lengths l_e) lies on a circle of radius R_c when the turning at each vertex
// is half the central angles alpha_e = 2 asin(l_e / 2 R_c) of its two edges, with R_c set by
// sum_e alpha_e = 2 pi; the turning is positive on the outer loop, negative on the others.
// With g_e = d alpha_e / d log l_e at fixed R (2 tan(alpha_e / 2)), R's own change is
// d log R = sum g_e d log l_e / sum g_e, so d alpha_e = g_e (d log l_e - d log R): symmetric in the
// edges, and for Yamabe (log l_e = (u_a + u_b) / 2 + const) symmetric in u too.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "ricci/flow/target.h"
#include "ricci/mesh/triangulation.h"

namespace ricci::detail {

//! Central angles of chords of lengths l on one circle, summing to 2 pi: 2 asin(l / 2R) with R by
//! bisection. When no such circle has its centre inside the polygon (one chord longer than the
//! rest together allow), the angles fall back to proportional to length. With `weights`, also
//! d angle / d log l at fixed R: 2 tan(angle / 2), or the angle itself in the fallback.
std::vector<double> central_angles(const std::vector<double>& l,
                                   std::vector<double>* weights = nullptr);

//! Per boundary loop, its edges in loop order: edge i joins vertex i and vertex i + 1.
std::vector<std::vector<int>> loop_edges(const Triangulation& mesh);

class CircleCondition {
 public:
  //! \throws InvalidArgumentError when a boundary loop's edges cannot be found.
  CircleCondition(const Triangulation& mesh, int outer_loop);

  //! target's curvature at every boundary vertex: the turning that puts its loop, with these
  //! edge lengths (per edge of the mesh; boundary edges never flip), on a circle.
  void set_target(const std::vector<double>& lengths, TargetCurvature& target) const;

  //! Keeps d target / d u at these lengths for apply().
  void linearize(const std::vector<double>& lengths);

  //! (d target / d u) du for the Euclidean Yamabe flow, per vertex (0 off the boundary).
  Eigen::VectorXd apply(const Eigen::VectorXd& du) const;

 private:
  struct Loop {
    std::vector<int> vertices, edges;
    double sign = 1;              // +1 on the outer loop
    std::vector<double> weights;  // d alpha_e / d log l_e at the linearization
  };
  int num_vertices_;
  std::vector<Loop> loops_;
};

}  // namespace ricci::detail
