// What the flow is asked (FlowOptions) and what it gives (FlowResult): the types every stage after
// the flow reads, without the solver (flow_solver.h).
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/scheme.h"
#include "ricci/flow/target.h"
#include "ricci/linear/linear_solver.h"
#include "ricci/linear/vertex_order.h"
#include "ricci/mesh/compact_mesh.h"

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
  //! Yamabe in E2 and S2: when flips begin on the input's triangulation, flip it first to the
  //! intrinsic Delaunay triangulation of the input's lambda-lengths (EdgeFlip::isometric), whose
  //! class is the canonical one; false keeps the input triangulation's class.
  bool delaunay_class = true;
  //! S2 on a closed genus-0 surface (run_ricci_flow, compute_ricci_flow): first walk to the
  //! stereographic lift of the flattened punctured mesh (spherical_start.h).
  bool stereographic_start = true;
  //! Ptolemy flips (Yamabe in E2 and H2) may make an edge from a vertex to itself (a loop), as
  //! the Delaunay triangulation of a metric can need: without, a flow can stall with a triangle
  //! that violates the triangle inequality and no flip left to mend it. Not a face with one edge
  //! on two sides (around a vertex of degree 1): flows that need those still stall. The common
  //! subdivision follows loops; the layouts of the flowed triangulation across a cut (plane cut
  //! open, Poincare disk) do not. The atlas asks for loops last, where its first attempt's flow
  //! wanted one (stalled_for_loops, loops_refused) and neither the other attempts nor the
  //! unfolding gave an atlas (docs/design.md).
  bool loops = false;
  //! With a start (RicciFlowSolver::solve) reached at once by flips: the start is Newton's first
  //! step from the flow's u (the atlas's linear cone model: H at u = 0 is the cotangent
  //! Laplacian), and is taken as Newton takes its steps, halved (twice at most) while it does not
  //! lower the squared residual (Armijo's test, search_line).
  bool start_is_a_step = false;
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
  //! A flip of the Euclidean metric of the input's lambda-lengths, before the flow (Yamabe in E2
  //! and S2, when edge flips begin: the input's intrinsic Delaunay triangulation, whose
  //! lambda-lengths define the discrete conformal class of Gillespie, Springborn and Crane 2021,
  //! whatever the input's triangulation). lambda and chord are then those lambda-lengths.
  bool isometric = false;
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
  //! Stalled with edge flips on, where a flip to an edge from a vertex to itself was refused
  //! (FlowOptions::loops off): the same target may be reached with loops.
  bool stalled_for_loops = false;
  //! Flips to an edge from a vertex to itself that the last Delaunay flips of the result's
  //! triangulation refused (each time one was tried; with FlowOptions::loops only those no
  //! Ptolemy flip makes): where > 0 it is not Delaunay there, and can hold slivers.
  int loops_refused = 0;

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
  //! Free vertices whose start was eased so that the jump to it needs no edge from a vertex to
  //! itself (FlowState::jump_eased); 0 where the start was jumped to as given, or walked to.
  int eased_start_vertices = 0;
  //! Jumps to a start made at once (as a trial point is, with flips), over the whole solve: the
  //! first, one per easing and per share of it tried (FlowState::jump_eased, halve_start), and
  //! those of a walk made again (finish_walk, start_flipping); 0 where none was tried (no flips, or
  //! not every flip a Ptolemy flip).
  int start_jumps = 0;
  //! The share of a start that is Newton's first step (FlowOptions::start_is_a_step) that the
  //! flow took: 1, or 1/2 or 1/4 where the whole step raised the squared residual.
  double start_share = 1;
  //! Yamabe in E2 and S2: the flips began from the intrinsic Delaunay triangulation of the input's
  //! lambda-lengths (EdgeFlip::isometric), the canonical discrete conformal class; false when the
  //! input was Delaunay already, or when the flow in that class stalled at the boundary and the
  //! input's own class, tried instead, is what this result is (input_class_because says why).
  bool delaunay_class = false;
  std::string input_class_because;
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

}  // namespace ricci
