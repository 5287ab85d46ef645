// The pieces of one Newton iteration of the flow (ricci_flow.h), each small enough to check on its
// own: the residual, the step direction (Newton in E2 and H2, Levenberg-Marquardt in S2), the
// line search and the stall window. Not installed API.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "flow/circle_condition.h"
#include "flow/delaunay.h"
#include "flow/hessian.h"
#include "flow/metric.h"
#include "linear/minres.h"
#include "mesh/clock.h"
#include "ricci/flow/flow_result.h"
#include "ricci/flow/target.h"
#include "ricci/linear/linear_solver.h"
#include "ricci/linear/vertex_order.h"

namespace ricci::detail {

//! Kbar - K on the rows of the free vertices.
Eigen::VectorXd free_residual(const Eigen::VectorXd& k, const TargetCurvature& target,
                              const std::vector<int>& free_index, int num_free);

//! max |r_i|, 0 for an empty r.
inline double max_abs(const Eigen::VectorXd& r) {
  return r.size() > 0 ? r.cwiseAbs().maxCoeff() : 0;
}

//! The relative residual an inexact Newton step is solved to: max |r| (quadratic convergence),
//! but no lower than a tenth of the tolerance over max |r| (about what the last step needs), in
//! [1e-12, 0.1].
double forcing_term(const Eigen::VectorXd& r, double tolerance);

//! max |K - Kbar| over every vertex with a curvature target (a pinned gauge vertex included).
double max_residual(const Eigen::VectorXd& k, const TargetCurvature& target);

//! "3 edges without a real length and 2 triangles violating the triangle inequality (...)".
std::string describe_invalid(const MetricState& state);

//! The rows of the unknowns: -1 where u is held fixed, and in E2 without fixed vertices at the
//! vertex pinned against the scaling (K is invariant under u + c).
std::vector<int> free_vertex_index(int num_vertices, Geometry geometry,
                                   const TargetCurvature& target);

//! Solves for the step: H du = r (E2, H2), or (H^2 + mu I) du = H r with mu = weight |r| (S2,
//! where H is indefinite and singular along the Moebius maps at the solution). The Hessian's
//! pattern and its symbolic analysis are kept until the triangulation or the free set changes.
class StepSolver {
 public:
  explicit StepSolver(LinearSolverKind kind) : solver_(kind) {}

  //! A new pattern: a new triangulation (flips) or another set of free vertices; `unflipped`:
  //! the mesh's own connectivity, which the vertex order was found for.
  void set_pattern(const Triangulation& mesh, const std::vector<int>& free_index, bool unflipped);
  //! A new solve (another target): its first step factorizes H.
  void begin_solve();
  //! H's patterns from kNestedDissectionRows free vertices on are analysed in this order
  //! (restricted to the free vertices) instead of METIS's own for each, while the triangulation is
  //! the mesh's own: not after flips (316,933 Delaunay flips of the 1.07M-face lion head made
  //! every factorization in it 13 times slower), nor for H^2 + mu I (S2), whose pattern couples
  //! 2-rings.
  void use_vertex_order(VertexOrder order) { order_ = std::move(order); }
  //! The step the line search took along the last direction: its length, and whether a longer
  //! trial point left a triangle invalid (LineSearch::blocked_by_validity; a shorter one may then
  //! still have been refused for descent). A full step, or one so blocked, lets the next solve try
  //! the held factorization: where one triangle at a hole's rim degenerates at every full step
  //! (pymeshfix's bunny at 8 cones, six steps of 1/2 in a row), the held factorization
  //! preconditions the next system as well as after a full step (the atlases of the real set and
  //! CGAL's at 8 cones: 1,970 factorizations to 1,866, none more on any file; the bunny's 7 to 5).
  void note_step(double alpha, bool blocked_by_validity) {
    step_reuses_factor_ = alpha == 1 || blocked_by_validity;
  }
  int num_free() const { return num_free_; }

  //! False when no shift makes the system factorizable, or the step is not finite. Once the line
  //! search has taken a full step (or one blocked by an invalid triangle: note_step), the last
  //! factorization of the step's system on this pattern (of an earlier H; in S2 of an earlier
  //! H^2 + mu I) preconditions MINRES on the current system to relative residual rtol (inexact
  //! Newton) for at most kStaleSolveIterations, and the system is factorized again only when that
  //! falls short, or when MINRES at the rate it last converged on that factor would need more.
  //! After a shortfall, the new factorization is first reused once the residual has fallen to
  //! kReuseFactorBelowResidual of what it was made at.
  bool solve(const MetricState& state, const Eigen::VectorXd& r, bool spherical, double lm_weight,
             double rtol, Eigen::VectorXd& du, FlowTimes& times);
  static constexpr double kReuseFactorBelowResidual = 0.25;
  static constexpr int kStaleSolveIterations = 8;
  //! A new pattern (after flips) is analysed in the last one's ordering where the factor's fill
  //! is at most this many times the last fill of an ordering found afresh.
  static constexpr double kReusedOrderFill = 1.1;

  //! d target / d u, for a target that depends on u (the free rows and columns).
  using Coupling = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;
  static constexpr int kMaxKrylovIterations = 300;
  //! An earlier factorization stays the preconditioner while MINRES, at the rate it last converged
  //! on it, would need at most this many iterations for the step's relative residual, and is
  //! replaced when MINRES needs more than kStaleKrylovIterations.
  static constexpr int kReuseFactorBelow = 12, kStaleKrylovIterations = 30;

  struct Krylov {
    bool factorized = true;  //!< H could be factorized (or an earlier factorization served)
    bool progress = false;   //!< MINRES reduced the residual and the step is finite
  };
  //! The (damped) Newton step of a target that depends on u: ((1 + damping) H - C) du = r with
  //! C du = coupling(du), symmetric and possibly indefinite, by MINRES preconditioned with a
  //! factorization of H, to relative residual rtol (the preconditioner's norm).
  Krylov solve_coupled(const MetricState& state, const Eigen::VectorXd& r, const Coupling& coupling,
                       double damping, double rtol, Eigen::VectorXd& du, FlowTimes& times);

  int num_analyses() const { return solver_.num_analyses(); }
  int num_factorizations() const { return solver_.num_factorizations(); }
  //! MINRES iterations, over every solve so far.
  int num_krylov_iterations() const { return krylov_iterations_; }

 private:
  // Assembles (unless H is assembled at state already) and factorizes the step's system; rhs is
  // r, or H r in S2.
  bool factorize(const MetricState& state, const Eigen::VectorXd& r, bool spherical,
                 double lm_weight, Eigen::VectorXd& rhs, FlowTimes& times, bool assembled = false);
  enum class Held { None, Hessian, Normal };  // what the factorization is of: -, H, H^2 + mu I
  // Whether the held factorization, if it is of this kind, is worth another MINRES solve to rtol
  // within max_iterations (true when its rate is not known yet).
  bool reuse_factor(Held kind, double rtol, int max_iterations) const;
  // Keeps MINRES's convergence factor per iteration on the held factorization.
  void note_rate(const MinresResult& m);
  // MINRES on A x = r, preconditioned with the held factorization (in single precision), into du.
  template <class Apply>
  MinresResult precondition_with_factor(const Apply& apply, const Eigen::VectorXd& r, double rtol,
                                        int max_iterations, Eigen::VectorXd& du, FlowTimes& times);

  // The free vertices' rows in the vertex order, or none (empty).
  std::vector<int> rows_in_order() const;
  // The pattern's assembler, built on first use.
  HessianAssembler& assembler();
  std::unique_ptr<HessianAssembler> assembler_;
  const Triangulation* mesh_ = nullptr;
  std::vector<int> free_index_;
  int num_free_ = 0;
  bool unflipped_ = true;
  VertexOrder order_;
  LinearSolver solver_;
  // The last analysis's ordering (E2, H2), and the fill of the last one found afresh.
  std::vector<int> last_order_;
  long fresh_fill_ = 0;
  SparseMatrix normal_matrix_;   // S2: H^2
  bool normal_pattern_ = false;  // normal_matrix_ holds H^2's pattern on this pattern
  bool analyzed_ = false;
  Held held_ = Held::None;      // the factorization on the current pattern
  double factor_residual_ = 0;  // max |r| when it was made
  double krylov_rate_ = 0;      // MINRES's last convergence factor per iteration on it; 0: unknown
  bool stale_fell_short_ = false;  // the last MINRES solve with an earlier factorization fell short
  // The last step was a full one, or one where a longer trial point left a triangle invalid
  // (note_step): Newton's regime, where H changes little from step to step. (In S2, directions
  // from an earlier factorization after every step cut short made the Yamabe flow stall on 3
  // components of gltron-recognizer-quad.obj that converge with fresh ones; after steps so blocked
  // none of its flows changes, measured, and Cura's Hellbot Magna's sphere, which stalled in 100
  // iterations, converges.)
  bool step_reuses_factor_ = false;
  int krylov_iterations_ = 0;
};

//! The outcome of the backtracking line search along du.
struct LineSearch {
  bool accepted = false;
  bool blocked_by_validity = false;  //!< a longer step left the set of valid triangles
  //! ... and a triangle it left invalid has a boundary edge, which no flip removes
  bool blocked_at_boundary = false;
  //! ... and a longer trial point stayed invalid where its flips refused one to a loop
  bool blocked_by_loop = false;
  //! ... and a boundary triangle stayed invalid after the trial point's Ptolemy flips, which
  //! mend every other
  bool blocked_at_boundary_after_flips = false;
  double alpha = 1;
  Eigen::VectorXd u, k;  //!< accepted point and its curvature
  MetricState state;     //!< the accepted state, or the last one tried
  //! When the accepted point needed Ptolemy flips: its triangulation, eta and the flips.
  std::optional<IntrinsicTriangulation> flipped;
  std::vector<double> flipped_eta;
  FlipReport flips;
};

//! The metric at u (lengths and angles) in `s.state`; where a triangle is invalid there and
//! flip_invalid holds with all_ptolemy(structure), first flipped to Delaunay on a copy (s.flipped,
//! s.flipped_eta, s.flips): valid then, but where a flip was refused (a self-loop, or rounding)
//! or a boundary triangle is invalid (no flip mends it). `loops` as make_delaunay's.
void evaluate_trial_point(const IntrinsicTriangulation& mesh, const ConformalStructure& structure,
                          const Eigen::VectorXd& u, bool flip_invalid, bool loops, LineSearch& s);

//! Armijo backtracking on |Kbar - K|^2 / 2 from u along du, halving at most max_halvings times,
//! never accepting a point where a triangle is invalid. With flip_invalid, a trial point whose
//! triangles are invalid is first flipped to Delaunay on a copy when every flip is a Ptolemy flip
//! (all_ptolemy: E2 and H2 Yamabe; the solver asks for it in H2 only after a stall without): the
//! Delaunay triangulation of any u is valid there, so the search follows the flow's energy across
//! triangulations instead of stopping at the first one's edge.
//! With circles, the target's boundary curvature is that of each trial point's lengths.
LineSearch search_line(const IntrinsicTriangulation& mesh, const ConformalStructure& structure,
                       const TargetCurvature& target, const std::vector<int>& free_index,
                       const Eigen::VectorXd& u, const Eigen::VectorXd& du, double phi,
                       int max_halvings, bool flip_invalid, bool loops,
                       const CircleCondition* circles = nullptr);

//! A flow whose residual is within this factor of the angle sums' round-off (curvature_round_off)
//! and that no step reduces has converged as far as double precision allows (on real meshes, such
//! stalls were 1.8 to 4 times the round-off; genuine stalls 1e8 times and more).
inline constexpr double kRoundOffMargin = 10;
//! Above this factor of the round-off where the flow started, triangles have degenerated on the
//! way and the round-off is no floor (measured: 1.8e5 on the 3-holed double torus, where flips
//! then reach 1e-12; 1.0 on the 1.07M-face lion head's unit disk).
inline constexpr double kDegeneratedRoundOff = 100;

//! A step of at most this length, cut by degenerating triangles, is a short step.
inline constexpr double kShortStep = 1.0 / 64;

//! Steps cut short by degenerating triangles for many iterations with little progress: the flow
//! is running into the boundary of the valid set, where no solution lies. Or fewer in a row, with
//! as little progress, where the longer trial points' Delaunay triangulation needs an edge from a
//! vertex to itself that the flips do not make (FlowOptions::loops). Stopped after 3 such steps
//! instead of 10, the atlases of the real set, CGAL's, 100 game assets and 120 furniture models
//! (453 outputs) and of 592 held-out files (579 outputs) came out the same, and so did the default
//! targets' 231 outputs of the real set and CGAL's; the 17 files of the first whose attempts
//! stalled so took 93 s instead of 106 (medians of 3 alternating batches, beside builds).
//! As few, where the caller flows on the double next (doubled_surface.h), where the Ptolemy flips
//! left a boundary triangle invalid, which no flip of the surface mends, and the residual fell by
//! less than a tenth over them: the unit disk's one solve on FreeSurfer's flat patch of a
//! hemisphere (18,654 faces) ran 34 iterations (2.3 s) where it now stops at 9
//! (docs/benchmarks.md#disks-whose-boundary-triangles-degenerate). Only there, where the flow that
//! follows flips the boundary's edges; for other flows it is not measured.
class StallWindow {
 public:
  static constexpr int kLength = 10;
  //! Short steps in a row whose longer trial points needed a loop the flips did not make, or
  //! stayed invalid at the boundary after their flips.
  static constexpr int kLoopLength = 3;
  //! Records an accepted step; true when the flow has stalled: kLength short steps in a row with
  //! the residual not halved, kLoopLength blocked by a refused loop with it not halved, or, with
  //! double_next, kLoopLength blocked by the boundary after flips with it down by less than a
  //! tenth.
  bool stalled(const LineSearch& step, const std::vector<double>& residual_history,
               bool double_next = false);
  //! After stalled() held: the steps in a row it judged by (kLength or kLoopLength).
  int window() const { return window_; }
  //! The number of short steps in a row so far.
  int short_steps() const { return short_steps_; }
  //! Without flips (EdgeFlips::WhenNeeded), whether the steps so far call for them, and why; ""
  //! when they do not. Each pattern is one of steps cut to keep triangles valid:
  //! - kLengthBeforeFlips steps in a row of at most kShortStep;
  //! - three in a row of at most 1/16, each no longer than the one before (the flow runs into
  //!   the valid set's boundary);
  //! - twice within the last six steps, a full step followed by one cut to at most 1/4 (Newton
  //!   bounces off that boundary).
  //! On the real meshes and CGAL's scans that converge without flips, the last two never came up
  //! (scripts/compare_flip_modes.py); on those that need flips, they came up to 59 iterations
  //! before the first.
  std::string flips_called_for() const;
  static constexpr int kLengthBeforeFlips = 2;

 private:
  int short_steps_ = 0;
  int loop_steps_ = 0;
  int boundary_steps_ = 0;
  int window_ = 0;
  // The accepted steps' lengths, negated where triangles cut them (the last few).
  std::vector<double> recent_;
};

}  // namespace ricci::detail
