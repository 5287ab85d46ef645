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

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/compact_mesh.h"
#include "ricci/linear_solver.h"
#include "ricci/scheme.h"
#include "ricci/target.h"
#include "ricci/vertex_order.h"

namespace ricci {

struct FlowProgress {
  int iteration = 0;
  double residual = 0;  //!< max |K - Kbar| over the vertices with a curvature target
};

//! When the flow flips edges to keep the triangulation (power) Delaunay (delaunay.h):
//! - WhenNeeded: on the input's triangulation, exactly as Never, until Newton cannot go on there
//!   (no step reduces the residual, or steps are cut to keep triangles valid as
//!   StallWindow::flips_called_for says), then with flips from where it stopped (from where Newton
//!   began when that was at most 3 iterations before), within the same iteration limit (after a
//!   walk to a stereographic start that the triangulation blocked, from the walk made again with
//!   flips); where the unit disk's one solve would start flips, the repeated flows run on the
//!   input's triangulation first (reach_circle_domain, with defer_flips and restart_with_flips);
//! - Always: before the first step and after every step;
//! - Never: the result stays on the input's triangulation.
enum class EdgeFlips { WhenNeeded, Always, Never };
//! "when-needed", "always", "never".
std::string to_string(EdgeFlips f);
//! Inverse of to_string. \throws InvalidArgumentError naming the choices.
EdgeFlips edge_flips_from_string(const std::string& name);

struct FlowOptions {
  //! Converged when max |K - Kbar| <= tolerance, or, where double precision cannot get there, when
  //! every vertex is within the attainable floor (FlowResult::attainable_residual).
  double tolerance = 1e-10;
  int max_iterations = 100;  //!< Newton iterations
  LinearSolverKind linear_solver = LinearSolverKind::Cholmod;
  int max_step_halvings = 40;  //!< line search: smallest step is 2^-max_step_halvings
  //! Edge flips; after flips the result lives on another triangulation of the same vertices.
  EdgeFlips edge_flips = EdgeFlips::WhenNeeded;
  //! S2 on a closed genus-0 surface (run_ricci_flow, compute_ricci_flow): first walk to the
  //! stereographic lift of the flattened punctured mesh (spherical_start.h).
  bool stereographic_start = true;
  //! Called once per iteration; returning false cancels the flow.
  std::function<bool(const FlowProgress&)> progress;
};

//! Wall-clock seconds per phase.
struct FlowTimes {
  double setup = 0, assembly = 0, analysis = 0, factorization = 0, solve = 0, line_search = 0,
         flips = 0, total = 0;
};

//! Why a flow stopped: converged; never started (an invalid initial metric, a circle pattern
//! that cannot exist); cancelled by the progress callback; at the iteration limit; stalled, no
//! step making progress on this triangulation (edge flips may help); or, with EdgeFlips::WhenNeeded
//! and flips deferred (RicciFlowSolver::defer_flips), where flips would have started.
enum class FlowStop { Converged, NotStarted, Cancelled, IterationLimit, Stalled, FlipsNeeded };

//! One edge flip of the flow, with what the common subdivision (common_subdivision.h) needs to
//! follow the input's edges through it. Before the flip, edge a-b is the diagonal of the
//! quadrilateral k, a, l, b of its faces (k, a, b) and (l, b, a); after it, k-l.
struct EdgeFlip {
  int edge = -1;
  //! Yamabe (eps = 0 at all four corners): Ptolemy's relation on the lambda-lengths, which keeps
  //! the discrete conformal class; otherwise the flip keeps the metric of that moment.
  bool ptolemy = false;
  //! Sides k-a, a-l, l-b, b-k and the diagonal a-b before the flip: lambda-lengths sqrt(2 eta)
  //! (used when ptolemy), and chords of the metric of that moment (2 sin(l/2) in S2, 2 sinh(l/2)
  //! in H2).
  std::array<double, 5> lambda{}, chord{};
};

struct FlowResult {
  bool converged = false;
  FlowStop stop = FlowStop::NotStarted;
  std::string failure;  //!< why the flow stopped, when !converged
  //! Stalled with edge flips on, at triangles that only a flip of a boundary edge could repair.
  bool stalled_at_boundary = false;

  Eigen::VectorXd u;                 //!< conformal factor per vertex
  Eigen::VectorXd radius;            //!< circle radius r(u) of the geometry; NaN where undefined
  Eigen::VectorXd curvature;         //!< K of the result
  Eigen::VectorXd target;            //!< Kbar; NaN where u was held fixed
  std::vector<double> edge_lengths;  //!< per edge of result_triangulation()
  int num_flips = 0;                 //!< edge flips done during this solve
  //! EdgeFlips::WhenNeeded: the iteration of this solve from which edge flips were on, and why
  //! the input's triangulation was not enough; -1 and "" when this solve did not turn them on.
  int flips_from_iteration = -1;
  std::string without_flips;
  int connectivity_changes = 0;  //!< flip rounds of this solve that changed the triangulation
  //! Every flipped edge since the input triangulation, in order (replays the flips), over every
  //! solve of the solver so far.
  std::vector<EdgeFlip> flip_sequence;
  //! The final connectivity when flips changed it (edge indices as in the input).
  std::optional<Triangulation> triangulation;
  double area = 0;  //!< total area in the background geometry

  int iterations = 0;
  double residual = 0;  //!< max |K - Kbar| at the end
  //! When the tolerance is below what double precision allows on this metric: the residual the
  //! angle sums' round-off allows (curvature_round_off, times 10; for a pinned gauge vertex their
  //! accumulated rounding), within which every vertex came; the flow counts as converged there.
  //! 0 when the tolerance was reached.
  double attainable_residual = 0;
  std::vector<double> residual_history;          //!< residual before each iteration, and at the end
  std::vector<double> step_history;              //!< accepted step length alpha per iteration
  int num_analyses = 0, num_factorizations = 0;  //!< of this solve
  int krylov_iterations = 0;  //!< MINRES iterations of this solve (see StepSolver)
  FlowTimes times;
};

//! The triangulation the result's edge lengths belong to: the flipped one, or the input's.
inline const Triangulation& result_triangulation(const CompactMesh& mesh, const FlowResult& r) {
  return r.triangulation ? *r.triangulation : mesh;
}

//! The flow on one mesh and conformal structure, kept between solves: the triangulation as
//! flipped, the structure's eta on it, u, and the Hessian's pattern with its symbolic analysis
//! (reused while neither the triangulation nor the set of free vertices changes). A solve starts
//! where the last one ended: solving for a target near the last one takes few iterations.
class RicciFlowSolver {
 public:
  //! Hessians of kNestedDissectionRows rows or more on the mesh's own triangulation (any free
  //! set; not after flips, not S2's H^2 + mu I, not with LDL^T) are analysed in `order`
  //! (vertex_order.h), or where that is empty or for another number of vertices, in one the
  //! solver starts finding at once from the mesh's vertex graph (not in S2, nor with LDL^T).
  //! \throws InvalidArgumentError when the structure was built for another mesh, or the options
  //!   are out of range.
  RicciFlowSolver(const CompactMesh& mesh, const ConformalStructure& structure,
                  FlowOptions options = {}, VertexOrder order = {});
  ~RicciFlowSolver();
  RicciFlowSolver(const RicciFlowSolver&) = delete;
  RicciFlowSolver& operator=(const RicciFlowSolver&) = delete;

  //! Runs the flow to `target` from the current state. With `start`, first walks u towards it in
  //! the longest valid steps (with flips when they are on; Ptolemy flips keep the conformal
  //! class), then Newton. With flips when needed, the progress callback may see the iteration at
  //! which flips began twice (before and after them).
  //! Never throws for non-convergence: the result says why.
  //! \throws InvalidTargetError for a target that admits no flow.
  FlowResult solve(const TargetCurvature& target, const Eigen::VectorXd* start = nullptr);

  //! Runs the Euclidean Yamabe flow to the metric whose boundary loops are circles: the interior
  //! curvature as in `target`, at each boundary vertex the turning of a circle through its loop's
  //! current chords (circle_boundary_target, presets.h; positive on loop `outer_loop`, negative on
  //! the others). One solve: the boundary target's change with u is part of the Jacobian, singular
  //! at the solution along the disk's Moebius maps, so the steps are Levenberg-Marquardt ones,
  //! solved by MINRES preconditioned with a factorization of H (kept while MINRES stays short).
  //! The result's target is the boundary curvature reached. Never throws for non-convergence.
  //! \throws InvalidArgumentError for another geometry or scheme, a closed surface or u held
  //!   fixed; InvalidTargetError as solve().
  FlowResult solve_circle_domain(const TargetCurvature& target, int outer_loop);

  //! EdgeFlips::WhenNeeded: with defer, a solve stops where Newton would start flips
  //! (FlowStop::FlipsNeeded), leaving the caller to choose another way or restart with them. (A
  //! walk to a start with u held fixed somewhere still turns flips on at once; no deferred solve
  //! has a start.)
  void defer_flips(bool defer);

  //! Back to the input triangulation, the input structure and u0 (with flips on from the start
  //! after restart_with_flips()).
  void restart();
  //! restart(), and from now on edge flips on from the start, as with EdgeFlips::Always; the next
  //! solve reports them needed from its iteration 0, because of `why`.
  void restart_with_flips(const std::string& why);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

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
