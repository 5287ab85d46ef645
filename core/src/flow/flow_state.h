// The flow's state on one mesh between solves (RicciFlowSolver's), and one solve as a sequence of
// named steps: flow_solver.cpp runs a solve, flow_newton.cpp takes one Newton step and decides
// where the flow stops, flow_flips.cpp keeps the triangulation Delaunay and walks to a start.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "flow/circle_condition.h"
#include "flow/delaunay.h"
#include "flow/flow_steps.h"
#include "ricci/flow/flow_result.h"
#include "ricci/flow/scheme.h"
#include "ricci/flow/target.h"
#include "ricci/mesh/compact_mesh.h"

namespace ricci::detail {

struct FlowState {
  FlowState(const CompactMesh& m, const ConformalStructure& s, FlowOptions o)
      : mesh(m),
        input_structure(s),
        options(std::move(o)),
        triangulation(m),
        structure(s),
        u(s.u0),
        flipping(options.edge_flips == EdgeFlips::Always),
        flips_from_start(flipping),
        steps(options.linear_solver) {}

  const CompactMesh& mesh;
  const ConformalStructure input_structure;
  const FlowOptions options;

  // Kept from one solve to the next.
  IntrinsicTriangulation triangulation;  // the input's, then as flipped
  ConformalStructure structure;          // eta changes with flips
  Eigen::VectorXd u;
  bool flipping;  // edge flips are on (EdgeFlips::WhenNeeded: once the input's were not enough)
  // With flips on, the line search flips trial points whose triangles are invalid by Ptolemy's
  // relation (delaunay.h, all_ptolemy): in E2 always; in H2 only after a solve got stuck on
  // triangles without (this solve). On the real meshes, flipped trial points made the genus-97
  // cura-zav-maxpro.stl converge where it stalled (in 11 iterations from the start, 20 after the
  // stall), and from the start they cost occt-head.stl (genus 6, 41 boundary loops) its
  // convergence: from iteration 7 on, full steps that flip thousands of edges each, the residual
  // falling 1.5 % per step.
  bool flip_trial_points = false;
  bool defer_flips = false;  // EdgeFlips::WhenNeeded: stop where flips would start
  bool double_next = false;  // RicciFlowSolver::double_next
  // EdgeFlips::Always, or since restart_with_flips(), whose reason the next solve reports.
  bool flips_from_start;
  std::string flipping_because;
  // EdgeFlips::WhenNeeded: a walk to a start that the input's triangulation blocked, from where
  // and to where; when flips start, the walk is made again with them.
  std::optional<std::pair<Eigen::VectorXd, Eigen::VectorXd>> blocked_walk;
  // Where a walk with flips stopped creeping towards its start (walk_to): if Newton stalls from
  // there, the flow goes back to that point and walks on, the whole way (run()). Where the jump
  // went to an eased start (jump_eased): if Newton stalls from there, the flow goes back to where
  // the jump began and walks to the start as given.
  struct UnfinishedWalk {
    Eigen::VectorXd start, u;
    IntrinsicTriangulation triangulation;
    std::vector<double> eta;
    MetricState metric;
    size_t flips_made = 0;  // of flip_sequence
    int num_flips = 0, connectivity_changes = 0;
    int loops_refused = 0;  // FlowResult::loops_refused of `triangulation`
    bool eased = false;
  };
  std::optional<UnfinishedWalk> unfinished_walk;
  // The state now, to come back to with a walk to `start`.
  UnfinishedWalk walk_from_here(const Eigen::VectorXd& start, bool eased) const;
  void finish_walk();
  // u at this solve's first Newton iteration. Flips that start by iteration kStartOverByIteration
  // start from there: on the real meshes and CGAL's scans whose flips started at iteration 2 or 3,
  // Newton then took as many iterations as with flips always, and from where it stopped up to 6
  // more (cura-robot-support.stl: 26 after the 3 without flips, against 31;
  // scripts/compare_flip_modes.py).
  Eigen::VectorXd newton_start;
  static constexpr int kStartOverByIteration = 3;
  std::vector<EdgeFlip> flip_sequence;
  // Yamabe in E2 and S2: when flips begin on the input's triangulation, it is first flipped to the
  // input metric's intrinsic Delaunay triangulation (make_input_delaunay), whose lambda-lengths
  // give the canonical discrete conformal class (Gillespie, Springborn, Crane 2021: the class of
  // the metric, not of its triangulation; the input's own class where it is Delaunay already).
  // The non-Delaunay elk.off torus: its flat torus's modulus is 3.656i with the input's class,
  // 3.812i with this one and with CEPS. S2's lambda-lengths are half the chords of the scaled input
  // lengths read as arcs: IPP's 3D sample's sphere, QC p95 6.97 in the input triangulation's class,
  // 3.14 in this one (CEPS 3.34). H2 keeps the input's class: its cut layouts follow the flips in
  // one overlay (common_subdivision.h).
  bool input_made_delaunay = false;
  // False after a solve in the canonical class stalled at the boundary (and until restart()).
  bool canonical_class = true;
  std::vector<int> free_index;  // of the pattern the step solver holds
  bool pattern_current = false;
  detail::StepSolver steps;

  // One solve.
  FlowResult result;
  FlowTimes times;
  MetricState metric;
  Eigen::VectorXd k;
  double lm_weight = 1;  // S2 and circles: mu = lm_weight * |r|
  detail::StallWindow stall;
  // solve_circle_domain(): the boundary loops on circles, whose target moves with u; goal is the
  // target at the current u (otherwise the solve's target).
  std::optional<detail::CircleCondition> circles;
  TargetCurvature goal;

  bool spherical() const { return structure.geometry == Geometry::Spherical; }
  bool hyperbolic() const { return structure.geometry == Geometry::Hyperbolic; }
  bool may_start_flipping() const {
    return !flipping && options.edge_flips == EdgeFlips::WhenNeeded;
  }
  void start_flipping(int iteration, const std::string& why);
  void use_free_vertices(const TargetCurvature& target);
  void keep_delaunay();
  void adopt_flips(detail::LineSearch& step);
  void walk_to(const Eigen::VectorXd& start, bool whole_way = false, bool ease = true);
  // The jump to `start` with Ptolemy flips (its result in `jump`), from `start` eased at the free
  // vertices that an edge from a vertex to itself would need; returns the start jumped to.
  Eigen::VectorXd jump_eased(const Eigen::VectorXd& start, LineSearch& jump);
  // A start that is Newton's first step (FlowOptions::start_is_a_step), jumped to as `eased` and
  // `jump`, halved while it does not lower the squared residual: `start` becomes the share taken,
  // `eased` and `jump` its jump.
  void halve_start(Eigen::VectorXd& start, Eigen::VectorXd& eased, LineSearch& jump);
  std::string precondition_failure(const TargetCurvature& target);
  std::string iterate(const TargetCurvature& target, int it);
  double attainable_floor(const TargetCurvature& target) const;
  double start_round_off = 0;  // max curvature_round_off where Newton started
  void normalize_scale(const TargetCurvature& target);
  void finish(const TargetCurvature& target);
  void update_goal() {
    if (circles && metric.valid()) circles->set_target(metric.lengths(), goal);
  }
  bool step_direction(const Eigen::VectorXd& r, Eigen::VectorXd& du);
  std::string step_failure;           // why step_direction() failed, when H was factorized
  bool blocked_by_triangles = false;  // the last line search met triangles that degenerate
  FlowResult run(const Eigen::VectorXd* start);
  FlowResult run_in_a_class(const Eigen::VectorXd* start);
};

}  // namespace ricci::detail
