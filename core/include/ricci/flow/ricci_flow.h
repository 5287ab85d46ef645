// Newton's method on the Ricci energy: the one algorithm behind all 18 schemes.
//
//   solve H du = Kbar - K over the free vertices, u += alpha du,
// with H = dK/du (hessian.h), alpha from a backtracking line search on |Kbar - K|^2 that never
// leaves the set where every triangle is valid. E2 fixes the scaling gauge by pinning one vertex
// when no u is held fixed; S2, whose Hessian is indefinite and singular along the sphere's
// Moebius maps at the solution, takes Levenberg-Marquardt steps (H^2 + mu I) du = H (Kbar - K)
// instead of Newton steps. Between steps, edge flips keep the triangulation (power) Delaunay
// (delaunay.h).
//
// RicciFlowSolver keeps the flow's state on one mesh (triangulation as flipped, conformal
// structure, u, the Hessian's pattern and symbolic analysis) from one solve to the next;
// compute_ricci_flow is the one-shot call.
#pragma once

#include <string>

#include "ricci/flow/flow_solver.h"
#include "ricci/flow/scheme.h"
#include "ricci/flow/target.h"
#include "ricci/mesh/compact_mesh.h"

namespace ricci {

//! The length scale applied to the input before initialization: 1 in E2; in H2 and S2 the scale
//! giving the area Gauss-Bonnet asks for (area 1 when fixed vertices leave it open), reduced in
//! S2 until every triangle's perimeter is at most pi.
double initial_length_scale(const CompactMesh& mesh, Geometry geometry,
                            const TargetCurvature& target);

//! Checks the target and builds the scheme's initial structure at initial_length_scale().
//! \throws InvalidTargetError, InvalidArgumentError
ConformalStructure prepare_flow(const CompactMesh& mesh, Geometry geometry,
                                const SchemeOptions& scheme, const TargetCurvature& target);

//! Runs the flow from structure.u0 (on a closed genus-0 surface in S2, by default, after a walk to
//! the stereographic start). Never throws for non-convergence: the result says why.
//! \throws InvalidTargetError, InvalidArgumentError for inputs that admit no flow.
FlowResult run_ricci_flow(const CompactMesh& mesh, const ConformalStructure& structure,
                          const TargetCurvature& target, const FlowOptions& options = {});

//! One call for the common case: prepare_flow, run_ricci_flow.
//! \throws ConvergenceError when the flow does not reach the tolerance, and what
//!   prepare_flow throws.
FlowResult compute_ricci_flow(const CompactMesh& mesh, Geometry geometry,
                              const SchemeOptions& scheme, const TargetCurvature& target,
                              const FlowOptions& options = {});

//! "ricci flow (GEOMETRY, SCHEME) on SUBJECT: FAILURE" (without " on SUBJECT" when it is empty):
//! the one message of a flow that did not converge.
std::string flow_failure_message(Geometry geometry, Scheme scheme, const FlowResult& result,
                                 const std::string& subject = "");

}  // namespace ricci
