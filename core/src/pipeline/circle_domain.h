// The unit disk and circle domain targets: the boundary curvature that puts every boundary loop
// on a circle (circle_boundary_target, presets.h), reached in one Newton solve or as a fixed point
// of flow -> circle_boundary_target by repeated flows; the layout is then moved onto the unit
// disk (not installed API).
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/flow_solver.h"
#include "ricci/pipeline/uniformization.h"

namespace ricci::detail {

//! The target that puts every boundary loop of a converged flow's metric on a circle
//! (circle_boundary_target of its boundary lengths).
using BoundaryRefit = std::function<TargetCurvature(const FlowResult&)>;

//! Runs the solver's flow on `mesh` until the boundary curvature of `target` changes by at most
//! options.boundary_tolerance under `refit`: Anderson-accelerated, falling back to the plain
//! iteration (and a cold start) where the accelerated target cannot be reached. Fills run.result,
//! run.totals and run.boundary_change; the result is marked unconverged when the iteration limit
//! is hit, or when the change has not fallen below its least for kUnsettledFlows flows: on the
//! real-mesh set, of the 16 fits that settled, 15 had a new least at every flow and one (the
//! annulus of openfoam-opencfd-text.stl, with flips) went 21 flows without one before settling
//! at flow 60; where it did not settle (occt-video-part.stl with flips) it went up and down
//! between 1e-3 and 1e-2 for 190 flows.
inline constexpr int kUnsettledFlows = 40;
void fit_boundary_to_circles(RicciFlowSolver& solver, const CompactMesh& mesh,
                             const BoundaryRefit& refit, TargetCurvature target,
                             const UniformizationOptions& options, Uniformization& run);

//! The flow on the surface's double (doubled_surface.h), as the disk preset calls on it: whether it
//! follows a stall at the boundary's triangles, and the flow itself where the run's last flow
//! stalled so: true when its result is in the run (false: not flowed, or run.double_failure says
//! why it gave none).
struct OnDouble {
  bool follows = false;
  std::function<bool()> flow;
};

//! The disk preset on `mesh`: with one_solve (the Euclidean Yamabe flow only) one solve with the
//! circle condition in the Jacobian (RicciFlowSolver::solve_circle_domain); where that does not
//! converge (unless cancelled), or without one_solve, fit_boundary_to_circles from the input's
//! metric. With EdgeFlips::WhenNeeded, where the one solve stops for flips
//! (FlowStop::FlipsNeeded), the repeated flows run on the input's triangulation as without flips;
//! where those fail too, the one solve (and, where that fails, the repeated flows) run with flips
//! from the start, as with EdgeFlips::Always. Where a one solve with flips (either) stalls at the
//! boundary's triangles, on_double.flow before the repeated flows. A one solve that stops
//! otherwise is followed by the repeated flows, which flip when needed.
//! Fills run as fit_boundary_to_circles does (the totals count every flow; the repeated flows'
//! failure names the double's after it); true when the result kept is a one solve's.
bool reach_circle_domain(RicciFlowSolver& solver, const CompactMesh& mesh, int outer_loop,
                         const TargetCurvature& target, const UniformizationOptions& options,
                         bool one_solve, const OnDouble& on_double, Uniformization& run);

//! The refit of a flow on `mesh` itself: its boundary edges are edges of the final metric.
BoundaryRefit refit_on_mesh(const CompactMesh& mesh, int outer_loop);

//! The circle through the points (algebraic least squares): centre and radius.
std::pair<Eigen::Vector2d, double> fit_circle(const std::vector<Eigen::Vector3d>& points,
                                              const std::vector<int>& which);

//! max | |z - c| - r | / r over the mesh's boundary loops, each against its fitted circle.
double circle_error(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh);

//! The points scaled and moved so that the circle fitted to the `boundary` points is the unit
//! circle; then, with center >= 0, the Moebius map of the unit disk taking point `center` to 0,
//! and with axis >= 0 the rotation taking point `axis` onto the positive real axis.
//! \throws InvalidArgumentError when center lies on the circle or axis at the centre.
std::vector<Eigen::Vector3d> normalize_to_unit_disk(std::vector<Eigen::Vector3d> points,
                                                    const std::vector<int>& boundary, int center,
                                                    int axis);

}  // namespace ricci::detail
