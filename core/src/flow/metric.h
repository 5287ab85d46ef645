// The discrete metric at a conformal factor u: edge lengths, corner angles and their
// derivatives, evaluated once per Newton iterate and shared by curvature and Hessian.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "ricci/flow/scheme.h"
#include "ricci/mesh/geometry.h"
#include "ricci/mesh/triangulation.h"

namespace ricci {

struct MetricState {
  std::vector<EdgeLength> edges;      //!< per edge: l and dl/du at both endpoints
  std::vector<TriangleAngles> faces;  //!< per face: corner angles and d angle / d l
  int num_invalid_edges = 0;          //!< edges whose length law has no solution
  int num_invalid_faces = 0;          //!< faces violating the triangle inequality
  int first_invalid_face = -1;
  bool valid() const { return num_invalid_edges == 0 && num_invalid_faces == 0; }
  //! Edge lengths as a plain array.
  std::vector<double> lengths() const;
};

//! Lengths and angles of the circle packing metric (eps, eta, u).
MetricState evaluate_metric(const Triangulation& mesh, const ConformalStructure& structure,
                            const Eigen::VectorXd& u);

//! The edge lengths alone (faces empty): the first half of evaluate_metric.
MetricState evaluate_lengths(const Triangulation& mesh, const ConformalStructure& structure,
                             const Eigen::VectorXd& u);
//! Whether every edge's length law has a solution and every face's lengths of `state` (from
//! evaluate_lengths) satisfy the triangle inequality: what validity needs, without the angles
//! (their arc tangents cost most of a metric). False: the metric is not valid.
bool lengths_admit_triangles(const Triangulation& mesh, Geometry geometry,
                             const MetricState& state);
//! In the plane, a k in 0 .. last + 1 no larger than the least k for which the lengths at
//! u + 2^-k d admit triangles (lengths_admit_triangles; last + 1: none up to last): the largest,
//! over the faces that fail at u + d (`at_whole_step`, evaluate_lengths there), of the first
//! halving at which that face alone could be admitted (to a slack above round-off). A walk's
//! halvings then cost their failing faces, not the mesh, until the whole test takes over at k.
//! 0 in the other geometries.
int first_halving_admitted(const Triangulation& mesh, const ConformalStructure& structure,
                           const Eigen::VectorXd& u, const Eigen::VectorXd& d,
                           const MetricState& at_whole_step, int last);
//! The corner angles of `state`'s lengths: the second half of evaluate_metric.
void evaluate_angles(const Triangulation& mesh, Geometry geometry, MetricState& state);

//! Recomputes edge e's length and the angles of its faces (after e was flipped or its eta
//! changed), keeping the invalid counts up to date.
void update_metric_at_edge(const Triangulation& mesh, const ConformalStructure& structure,
                           const Eigen::VectorXd& u, int e, MetricState& state);

//! Discrete Gauss curvature: 2 pi - sum of angles inside, pi - sum on the boundary.
//! \pre state.valid()
Eigen::VectorXd curvature(const Triangulation& mesh, const MetricState& state);

//! The round-off in the curvature of each vertex's angle sum: unit round-off times, over its
//! faces, (a^2 + b^2 + c^2) / (4 area), the condition of the law of cosines (the Euclidean area
//! of the side lengths, from Kahan's formula, in every geometry). Its maximum is what a residual
//! can be brought down to. \pre state.valid()
Eigen::VectorXd curvature_round_off(const Triangulation& mesh, const MetricState& state);

//! Total area of the metric in its background geometry. \pre state.valid()
double total_area(const Triangulation& mesh, Geometry geometry, const MetricState& state);

}  // namespace ricci
