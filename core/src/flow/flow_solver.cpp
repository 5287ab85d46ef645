#include "ricci/flow/flow_solver.h"

// RicciFlowSolver: one solve from its setup to its result, and the solver's public calls.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

#include "flow/flow_state.h"
#include "flow/pattern_obstruction.h"
#include "ricci/mesh/errors.h"

namespace ricci {

using detail::Clock;
using detail::seconds_since;

// Why no flow can start here, or "".
std::string detail::FlowState::precondition_failure(const TargetCurvature& target) {
  if (!metric.valid()) {
    return "the initial metric of this scheme is not valid in " + to_string(structure.geometry) +
           " geometry: " + detail::describe_invalid(metric) +
           "; try another scheme (tangential packing is always valid)";
  }
  return circle_pattern_obstruction(triangulation, structure, target);
}

// E2 without fixed vertices: the scale of the input's total area.
void detail::FlowState::normalize_scale(const TargetCurvature& target) {
  if (structure.geometry != Geometry::Euclidean || target.num_fixed() > 0) return;
  const double area = total_area(triangulation, Geometry::Euclidean, metric);
  u.array() += 0.5 * std::log(mesh.input_area() / area);
  metric = evaluate_metric(triangulation, structure, u);
  k = curvature(triangulation, metric);
  result.residual = detail::max_residual(k, target);
}

void detail::FlowState::finish(const TargetCurvature& target) {
  const Geometry g = structure.geometry;
  FlowResult& r = result;
  r.u = u;
  r.curvature = k;
  r.edge_lengths = metric.lengths();
  r.area = metric.valid() ? total_area(triangulation, g, metric)
                          : std::numeric_limits<double>::quiet_NaN();
  r.radius.resize(u.size());
  r.target.resize(u.size());
  for (int v = 0; v < u.size(); ++v) {
    r.radius[v] = radius_from_conformal_factor(g, u[v]);
    r.target[v] =
        target.is_fixed(v) ? std::numeric_limits<double>::quiet_NaN() : target.curvature[v];
  }
  r.flip_sequence = flip_sequence;
  if (!flip_sequence.empty()) r.triangulation = triangulation;
  structure.u0 = u;
}

RicciFlowSolver::RicciFlowSolver(const CompactMesh& mesh, const ConformalStructure& structure,
                                 FlowOptions options, VertexOrder order) {
  if (!(options.tolerance > 0) || options.max_iterations < 0) {
    throw InvalidArgumentError(
        "ricci flow: tolerance must be positive and the iteration limit non-negative");
  }
  const int nv = mesh.num_vertices();
  if (static_cast<int>(structure.eps.size()) != nv || structure.u0.size() != nv ||
      static_cast<int>(structure.eta.size()) != mesh.num_edges()) {
    throw InvalidArgumentError("ricci flow: the conformal structure was built for another mesh");
  }
  state_ = std::make_unique<detail::FlowState>(mesh, structure, std::move(options));
  // S2 analyses H^2 + mu I in its own ordering, and LDL^T takes none.
  const bool ordered = structure.geometry != Geometry::Spherical &&
                       state_->options.linear_solver == LinearSolverKind::Cholmod;
  if (order.num_vertices() != nv && ordered) order = VertexOrder::start(nv, mesh.faces());
  state_->steps.use_vertex_order(std::move(order));
}

RicciFlowSolver::~RicciFlowSolver() = default;

void RicciFlowSolver::defer_flips(bool defer) {
  state_->defer_flips = defer;
}

void RicciFlowSolver::double_next(bool next) {
  state_->double_next = next;
}

void RicciFlowSolver::restart_with_flips(const std::string& why) {
  detail::FlowState& s = *state_;
  if (!s.flips_from_start) s.flipping_because = why;
  s.flips_from_start = true;
  restart();
}

void RicciFlowSolver::restart() {
  detail::FlowState& s = *state_;
  s.triangulation = IntrinsicTriangulation(s.mesh);
  s.structure = s.input_structure;
  s.u = s.input_structure.u0;
  s.flipping = s.flips_from_start;
  s.blocked_walk.reset();
  s.flip_sequence.clear();
  s.input_made_delaunay = false;
  s.canonical_class = true;
  s.pattern_current = false;
}

// A solve that flipped the input to its intrinsic Delaunay triangulation and then stalled at the
// boundary, where no flip helps, is made again in the input's own class: the classes differ, and
// the input's can hold where the other's boundary triangles degenerate (OpenFOAM's propeller tip
// with u = 0 on its boundary).
FlowResult detail::FlowState::run_in_a_class(const Eigen::VectorXd* start) {
  const IntrinsicTriangulation before = triangulation;
  const ConformalStructure structure_before = structure;
  const Eigen::VectorXd u_before = u;
  const std::vector<EdgeFlip> flips_before = flip_sequence;
  const bool flipping_before = flipping;
  FlowResult r = run(start);
  if (r.converged || !r.delaunay_class || !r.stalled_at_boundary) return r;
  const std::string why =
      "in the class of the input's intrinsic Delaunay triangulation, " + r.failure;
  triangulation = before;
  structure = structure_before;
  u = u_before;
  flip_sequence = flips_before;
  flipping = flipping_before;
  canonical_class = false;
  pattern_current = false;
  FlowResult again = run(start);
  again.input_class_because = why;
  return again;
}

FlowResult RicciFlowSolver::solve(const TargetCurvature& target, const Eigen::VectorXd* start) {
  detail::FlowState& s = *state_;
  check_target(s.mesh, s.structure.geometry, target);
  s.circles.reset();
  s.goal = target;
  return s.run_in_a_class(start);
}

FlowResult RicciFlowSolver::solve_circle_domain(const TargetCurvature& target, int outer_loop) {
  detail::FlowState& s = *state_;
  if (s.structure.geometry != Geometry::Euclidean || !is_yamabe(s.structure) ||
      target.num_fixed() > 0 || s.mesh.is_closed() || s.mesh.genus() != 0 || outer_loop < 0 ||
      outer_loop >= s.mesh.num_boundary_loops()) {
    throw InvalidArgumentError(
        "ricci flow: boundary loops on circles in one solve need the Euclidean Yamabe flow on a "
        "genus-0 surface with boundary, a curvature target at every vertex and one of its "
        "boundary loops as the outer one");
  }
  check_target(s.mesh, s.structure.geometry, target);
  s.circles.emplace(s.mesh, outer_loop);
  s.goal = target;
  FlowResult r = s.run_in_a_class(nullptr);
  s.circles.reset();
  return r;
}

FlowResult detail::FlowState::run(const Eigen::VectorXd* start) {
  FlowState& s = *this;
  const TargetCurvature& target = s.goal;
  const auto begin = Clock::now();
  const int analyses = s.steps.num_analyses(), factorizations = s.steps.num_factorizations(),
            krylov = s.steps.num_krylov_iterations();
  s.result = FlowResult();
  if (!s.flipping_because.empty()) {
    s.result.flips_from_iteration = 0;
    s.result.without_flips = std::move(s.flipping_because);
    s.flipping_because.clear();
  }
  s.times = FlowTimes();
  s.lm_weight = 1;
  s.stall = detail::StallWindow();
  s.blocked_walk.reset();
  s.unfinished_walk.reset();
  s.flip_trial_points = false;
  s.steps.begin_solve();
  s.use_free_vertices(target);
  s.metric = evaluate_metric(s.triangulation, s.structure, s.u);
  s.times.setup = seconds_since(begin);
  FlowResult& r = s.result;
  r.failure = s.precondition_failure(target);
  if (!r.failure.empty()) {
    s.k = s.metric.valid() ? curvature(s.triangulation, s.metric)
                           : Eigen::VectorXd::Constant(s.u.size(), std::nan(""));
  } else {
    s.keep_delaunay();
    // With u held at some vertices, Newton converges from wherever the walk stopped, to another
    // metric than the start's: the walk is made again with flips at once. Where the start is no
    // metric on this triangulation, a walk without flips cannot reach it: made with them at once
    // (the cow's atlas at 8 cones: its flow 0.43 s to 0.37 s, medians of 3).
    if (start && start->allFinite() && target.num_fixed() > 0 && s.may_start_flipping() &&
        !evaluate_metric(s.triangulation, s.structure, *start).valid()) {
      s.blocked_walk.emplace(s.u, *start);
    } else if (start) {
      s.walk_to(*start);
    }
    if (s.blocked_walk && target.num_fixed() > 0) {
      s.start_flipping(0, "the walk to the start was blocked by degenerating triangles");
    }
    s.k = curvature(s.triangulation, s.metric);
    s.newton_start = s.u;
    s.start_round_off = curvature_round_off(s.triangulation, s.metric).maxCoeff();
    for (int it = 0;; ++it) {
      s.update_goal();
      r.residual = detail::max_residual(s.k, target);
      r.residual_history.push_back(r.residual);
      r.iterations = it;
      if (s.options.progress && !s.options.progress({it, r.residual})) {
        r.failure = "cancelled at iteration " + std::to_string(it);
        r.stop = FlowStop::Cancelled;
        break;
      }
      if (r.residual <= s.options.tolerance || s.steps.num_free() == 0) {
        r.converged = true;
        r.stop = FlowStop::Converged;
        break;
      }
      // Within what double precision allows, above a tolerance it does not: converged there.
      if (r.residual <= 1e3 * s.options.tolerance) {
        r.attainable_residual = s.attainable_floor(target);
        if (r.attainable_residual > 0) {
          r.converged = true;
          r.stop = FlowStop::Converged;
          break;
        }
      }
      if (it >= s.options.max_iterations) {
        std::ostringstream m;
        m << "no convergence in " << it << " iterations: max |K - Kbar| = " << r.residual
          << " > tolerance " << s.options.tolerance
          << "; raise the iteration limit, or loosen the tolerance";
        r.failure = m.str();
        r.stop = FlowStop::IterationLimit;
        break;
      }
      const std::string stop = s.iterate(target, it);
      if (r.attainable_residual > 0) {
        r.converged = true;
        r.stop = FlowStop::Converged;
        break;
      }
      if (!stop.empty() && s.flipping && s.blocked_by_triangles && s.hyperbolic() &&
          !s.flip_trial_points && all_ptolemy(s.structure)) {
        // The step that was not taken is taken again, with flipped trial points.
        s.flip_trial_points = true;
        s.stall = detail::StallWindow();
        r.stalled_at_boundary = r.stalled_for_loops = false;
        r.residual_history.pop_back();
        --it;
        continue;
      }
      if (!stop.empty() && s.unfinished_walk) {
        // Newton stalled from where the walk stopped creeping: back there, the walk the whole
        // way, and Newton again from its end (the flips Newton made are undone; its iterations
        // stay in the histories and count towards the limit).
        s.finish_walk();
        r.stalled_at_boundary = r.stalled_for_loops = false;
        r.residual_history.pop_back();
        --it;
        continue;
      }
      // With circles, a stop that no degenerating triangle caused is left to the repeated flows
      // (circle_domain.h), which run on the input's triangulation as far as it goes.
      const bool flips_help =
          !stop.empty() && s.may_start_flipping() && (!s.circles || s.blocked_by_triangles);
      if (flips_help && !s.defer_flips) {
        // The step that was not taken is taken again on the flipped triangulation.
        s.start_flipping(it, stop);
        r.residual_history.pop_back();
        --it;
        continue;
      }
      if (!stop.empty()) {
        r.failure = stop;
        r.stop = flips_help ? FlowStop::FlipsNeeded : FlowStop::Stalled;
        break;
      }
    }
    s.unfinished_walk.reset();  // a copy of the triangulation
    if (r.converged) s.normalize_scale(target);
    s.update_goal();
    r.residual = detail::max_residual(s.k, target);
  }
  s.finish(target);
  r.num_analyses = s.steps.num_analyses() - analyses;
  r.num_factorizations = s.steps.num_factorizations() - factorizations;
  r.krylov_iterations = s.steps.num_krylov_iterations() - krylov;
  s.times.total = seconds_since(begin);
  r.times = s.times;
  return std::move(s.result);
}

}  // namespace ricci
