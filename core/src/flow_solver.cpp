// RicciFlowSolver: the flow's state between solves, and one solve as a sequence of named steps.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

#include "circle_condition.h"
#include "delaunay.h"
#include "flow_steps.h"
#include "pattern_obstruction.h"
#include "ricci/errors.h"
#include "ricci/ricci_flow.h"

namespace ricci {

using detail::Clock;
using detail::seconds_since;

struct RicciFlowSolver::State {
  State(const CompactMesh& m, const ConformalStructure& s, FlowOptions o)
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
  // EdgeFlips::Always, or since restart_with_flips(), whose reason the next solve reports.
  bool flips_from_start;
  std::string flipping_because;
  // EdgeFlips::WhenNeeded: a walk to a start that the input's triangulation blocked, from where
  // and to where; when flips start, the walk is made again with them.
  std::optional<std::pair<Eigen::VectorXd, Eigen::VectorXd>> blocked_walk;
  // u at this solve's first Newton iteration. Flips that start by iteration kStartOverByIteration
  // start from there: on the real meshes and CGAL's scans whose flips started at iteration 2 or 3,
  // Newton then took as many iterations as with flips always, and from where it stopped up to 6
  // more (cura-robot-support.stl: 26 after the 3 without flips, against 31;
  // scripts/compare_flip_modes.py).
  Eigen::VectorXd newton_start;
  static constexpr int kStartOverByIteration = 3;
  std::vector<EdgeFlip> flip_sequence;
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
  void walk_to(const Eigen::VectorXd& start);
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
};

// The Newton (S2: Levenberg-Marquardt) direction. With circles, the target's own change with u
// is part of the Jacobian J = H - d goal/du, which is singular at the solution along the disk's
// Moebius maps (they act on u as u + log |f'|) and indefinite away from it: Levenberg-Marquardt
// steps (J + mu H) du = r with mu = lm_weight |r| in [1e-4, 1], by MINRES preconditioned with H,
// to a relative residual that falls with |r| (inexact Newton, superlinear). Preconditioned, the
// Moebius directions have eigenvalue mu and the others at least about 1/2 (the disk's Steklov
// eigenvalues k >= 2 give 1 - 1/k): the floor keeps the steps along the Moebius maps, driven by
// the residual's round-off, small enough that their second-order error stays below the tolerance
// (with 0, the 67k-face lion head crept from 1e-9 to 1e-11 in 10 cut steps), and costs the
// others a factor of about 2e-4 per step. The round-off's Moebius component is left in the
// residual (1.5e-12 at the boundary of the 1.07M-face lion head), within the tolerance.
bool RicciFlowSolver::State::step_direction(const Eigen::VectorXd& r, Eigen::VectorXd& du) {
  step_failure.clear();
  const double rtol = detail::forcing_term(r, options.tolerance);
  if (!circles) return steps.solve(metric, r, spherical(), lm_weight, rtol, du, times);
  circles->linearize(metric.lengths());
  const auto coupling = [this](const Eigen::VectorXd& x) {
    Eigen::VectorXd full = Eigen::VectorXd::Zero(u.size());
    for (int v = 0; v < u.size(); ++v)
      if (free_index[v] >= 0) full[v] = x[free_index[v]];
    const Eigen::VectorXd c = circles->apply(full);
    Eigen::VectorXd out(x.size());
    for (int v = 0; v < u.size(); ++v)
      if (free_index[v] >= 0) out[free_index[v]] = c[v];
    return out;
  };
  const double damping = std::clamp(lm_weight * r.cwiseAbs().maxCoeff(), 1e-4, 1.0);
  const detail::StepSolver::Krylov krylov =
      steps.solve_coupled(metric, r, coupling, damping, rtol, du, times);
  if (krylov.factorized && !krylov.progress)
    step_failure = "MINRES made no progress on the damped step";
  return krylov.factorized && krylov.progress;
}

void RicciFlowSolver::State::use_free_vertices(const TargetCurvature& target) {
  std::vector<int> index =
      detail::free_vertex_index(mesh.num_vertices(), structure.geometry, target);
  if (index != free_index) pattern_current = false;
  free_index = std::move(index);
  if (!pattern_current) steps.set_pattern(triangulation, free_index, flip_sequence.empty());
  pattern_current = true;
}

// Flips to (power) Delaunay; a changed connectivity needs a new Hessian pattern and analysis.
void RicciFlowSolver::State::keep_delaunay() {
  if (!flipping) return;
  const auto t = Clock::now();
  const FlipReport flips =
      make_delaunay(triangulation, structure, u, metric, 10 * mesh.num_edges());
  result.num_flips += flips.flips;
  flip_sequence.insert(flip_sequence.end(), flips.sequence.begin(), flips.sequence.end());
  // A flip that was undone leaves the same triangles in other face slots: the pattern's per-face
  // entries change too.
  if (!flips.sequence.empty()) {
    ++result.connectivity_changes;
    steps.set_pattern(triangulation, free_index, false);
  }
  times.flips += seconds_since(t);
}

// The triangulation a line search flipped to reach its accepted point.
void RicciFlowSolver::State::adopt_flips(detail::LineSearch& step) {
  triangulation = std::move(*step.flipped);
  structure.eta = std::move(step.flipped_eta);
  result.num_flips += step.flips.flips;
  flip_sequence.insert(flip_sequence.end(), step.flips.sequence.begin(), step.flips.sequence.end());
  ++result.connectivity_changes;
  steps.set_pattern(triangulation, free_index, false);
}

// EdgeFlips::WhenNeeded: flips from here on, starting from the current u.
void RicciFlowSolver::State::start_flipping(int iteration, const std::string& why) {
  flipping = true;
  result.flips_from_iteration = iteration;
  result.without_flips = why;
  stall = detail::StallWindow();
  lm_weight = 1;
  if (blocked_walk) {
    // Newton got stuck after a blocked walk: the walk again from its origin, with flips, as it
    // goes with flips always (it costs no factorization).
    u = blocked_walk->first;
    metric = evaluate_metric(triangulation, structure, u);
    keep_delaunay();
    const Eigen::VectorXd start = std::move(blocked_walk->second);
    blocked_walk.reset();
    walk_to(start);
  } else {
    if (iteration <= kStartOverByIteration) {
      u = newton_start;
      metric = evaluate_metric(triangulation, structure, u);
    }
    keep_delaunay();
  }
  k = curvature(triangulation, metric);
}

// Moves u towards `start` in the longest valid steps, flipping to Delaunay after each when flips
// are on. Without them, the walk ends where no step of 1e-6 of the way is valid, or after three
// steps in a row of at most 1/64 of the way; when needed, that is remembered, and the walk made
// again with flips once Newton gets stuck on this triangulation.
void RicciFlowSolver::State::walk_to(const Eigen::VectorXd& start) {
  if (!start.allFinite()) return;
  const Eigen::VectorXd origin = u;
  int short_steps = 0;
  for (int step = 0; step < 200; ++step) {
    const Eigen::VectorXd d = start - u;
    double alpha = 1;
    MetricState trial;
    for (; alpha > 1e-6; alpha *= 0.5) {
      trial = evaluate_metric(triangulation, structure, u + alpha * d);
      if (trial.valid()) break;
    }
    // Without flips, steps that stay short only creep along the valid set's boundary.
    short_steps = alpha <= detail::kShortStep ? short_steps + 1 : 0;
    if (!trial.valid() || (!flipping && short_steps > detail::StallWindow::kLengthBeforeFlips)) {
      if (may_start_flipping()) blocked_walk.emplace(origin, start);
      return;
    }
    u += alpha * d;
    metric = std::move(trial);
    keep_delaunay();
    if (alpha == 1) return;
  }
}

// Why no flow can start here, or "".
std::string RicciFlowSolver::State::precondition_failure(const TargetCurvature& target) {
  if (!metric.valid()) {
    return "the initial metric of this scheme is not valid in " + to_string(structure.geometry) +
           " geometry: " + detail::describe_invalid(metric) +
           "; try another scheme (tangential packing is always valid)";
  }
  return circle_pattern_obstruction(triangulation, structure, target);
}

// The floor the residual has reached when every vertex is within the tolerance or what double
// precision allows it (kRoundOffMargin times curvature_round_off), and some vertex is above the
// tolerance only because of that, else 0. In E2 without fixed vertices the pinned
// gauge vertex has no unknown of its own: by Gauss-Bonnet its residual is the sum of all
// residuals less the others'. For a target that satisfies Gauss-Bonnet that sum is the angle
// sums' defect sum K - 2 pi chi, 0 in exact arithmetic and their accumulated rounding as computed
// (1.3e-10 on a million vertices, the same at every u near the solution); the others' round-off
// adds to it (as a random walk: the root of the sum of squares).
// A floor that triangles made nearly degenerate by the flow raise (their angles' round-off
// kDegeneratedRoundOff times that where Newton started, and more) is none: a stall or flips
// decide there.
double RicciFlowSolver::State::attainable_floor(const TargetCurvature& target) const {
  const Eigen::VectorXd noise = curvature_round_off(triangulation, metric);
  if (noise.maxCoeff() > detail::kDegeneratedRoundOff * start_round_off) return 0;
  const double floor = detail::kRoundOffMargin * noise.maxCoeff();
  const Eigen::VectorXd r = detail::free_residual(k, target, free_index, steps.num_free());
  const double free_max = detail::max_abs(r);
  if (free_max > std::max(floor, options.tolerance)) return 0;
  double reached = free_max > options.tolerance ? floor : 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (free_index[v] >= 0 || target.is_fixed(v)) continue;
    const double pinned = std::abs(k[v] - target.curvature[v]);
    if (pinned <= options.tolerance) continue;
    // The angle sums' Gauss-Bonnet defect as computed (a target's own defect is no round-off).
    long double sum = -2 * static_cast<long double>(kPi) * mesh.euler_characteristic();
    for (int w = 0; w < mesh.num_vertices(); ++w) sum += k[w];
    const double pinned_floor =
        static_cast<double>(std::abs(sum)) + detail::kRoundOffMargin * noise.norm();
    if (pinned > pinned_floor) return 0;
    reached = std::max(reached, pinned_floor);
  }
  return reached;
}

// One Newton (S2: Levenberg-Marquardt) iteration; "" when it moved, else why the flow stops.
std::string RicciFlowSolver::State::iterate(const TargetCurvature& target, int it) {
  const Eigen::VectorXd r = detail::free_residual(k, target, free_index, steps.num_free());
  Eigen::VectorXd du;
  std::ostringstream s;
  blocked_by_triangles = false;
  if (!step_direction(r, du)) {
    if (step_failure.empty()) {
      s << "the Hessian could not be factorized at iteration " << it
        << " (max |K - Kbar| = " << result.residual << "); the metric is close to degenerate";
    } else {
      s << step_failure << " at iteration " << it << " (max |K - Kbar| = " << result.residual
        << ")";
    }
    return s.str();
  }
  const auto t = Clock::now();
  detail::LineSearch step = detail::search_line(triangulation, structure, target, free_index, u, du,
                                                0.5 * r.squaredNorm(), options.max_step_halvings,
                                                flipping && (flip_trial_points || !hyperbolic()),
                                                circles ? &*circles : nullptr);
  times.line_search += seconds_since(t);
  blocked_by_triangles = step.blocked_by_validity;
  const char* flips_help = flipping ? "" : " on this triangulation (edge flips help)";
  // Kbar = 0 on a closed surface is its uniformization: the metric exists, only the flow missed it.
  const bool exists =
      mesh.is_closed() && target.num_fixed() == 0 && target.curvature.cwiseAbs().maxCoeff() == 0;
  const char* exists_note =
      "; a metric of this target exists for every closed surface (uniformization), this flow did "
      "not reach it: try the tangential scheme";
  // Euclidean (and, with flipped trial points, hyperbolic) Yamabe flips to a valid triangulation
  // at every u, except across the boundary (uniformize() then flows on the surface doubled along
  // it, doubled_surface.h).
  const char* boundary_note =
      "; triangles at the boundary degenerate, and no edge flip of this surface removes a "
      "boundary edge: try the tangential scheme, whose triangles are always valid";
  const bool at_boundary = flipping && step.blocked_at_boundary;
  if (!step.accepted) {
    // A tolerance below what double precision allows here: the floor is convergence.
    result.attainable_residual = attainable_floor(target);
    if (result.attainable_residual > 0) return "";
    s << "stalled at iteration " << it << " with max |K - Kbar| = " << result.residual
      << ": no step of length >= 2^-" << options.max_step_halvings << " reduces the residual";
    if (!step.state.valid())
      s << " while keeping every triangle valid (" << detail::describe_invalid(step.state) << ")";
    if (exists) {
      s << exists_note;
    } else if (at_boundary) {
      s << boundary_note;
      result.stalled_at_boundary = true;
    } else {
      s << "; the solution may not exist" << (flipping ? " for this mesh" : flips_help)
        << ", or try another scheme";
    }
    return s.str();
  }
  const std::vector<double>& history = result.residual_history;
  if (stall.stalled(step, history)) {
    s << "stalled at iteration " << it << ": for " << detail::StallWindow::kLength
      << " iterations the step was cut below 1/64 to keep triangles from degenerating, and "
         "max |K - Kbar| only went from "
      << history[history.size() - detail::StallWindow::kLength] << " to " << result.residual;
    if (exists) {
      s << exists_note;
    } else if (at_boundary) {
      s << boundary_note;
      result.stalled_at_boundary = true;
    } else {
      s << "; the target is not reachable" << (flipping ? " even with edge flips" : flips_help)
        << ", or try the tangential scheme, whose triangles are always valid";
    }
    return s.str();
  }
  if (spherical() || circles)
    lm_weight = step.alpha == 1 ? std::max(lm_weight / 4, 1e-8) : std::min(lm_weight * 8, 1e8);
  result.step_history.push_back(step.alpha);
  steps.note_step(step.alpha);
  u = std::move(step.u);
  metric = std::move(step.state);
  const int flips_before = result.num_flips;
  if (step.flipped) adopt_flips(step);
  keep_delaunay();
  k = result.num_flips > flips_before + step.flips.flips ? curvature(triangulation, metric)
                                                         : std::move(step.k);
  if (may_start_flipping()) {
    const std::string why = stall.flips_called_for();
    if (!why.empty()) {
      const std::string reason = "up to iteration " + std::to_string(it) + ", " + why;
      if (defer_flips) {
        blocked_by_triangles = true;
        return reason;
      }
      start_flipping(it + 1, reason);
    }
  }
  return "";
}

// E2 without fixed vertices: the scale of the input's total area.
void RicciFlowSolver::State::normalize_scale(const TargetCurvature& target) {
  if (structure.geometry != Geometry::Euclidean || target.num_fixed() > 0) return;
  const double area = total_area(triangulation, Geometry::Euclidean, metric);
  u.array() += 0.5 * std::log(mesh.input_area() / area);
  metric = evaluate_metric(triangulation, structure, u);
  k = curvature(triangulation, metric);
  result.residual = detail::max_residual(k, target);
}

void RicciFlowSolver::State::finish(const TargetCurvature& target) {
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
  state_ = std::make_unique<State>(mesh, structure, std::move(options));
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

void RicciFlowSolver::restart_with_flips(const std::string& why) {
  State& s = *state_;
  if (!s.flips_from_start) s.flipping_because = why;
  s.flips_from_start = true;
  restart();
}

void RicciFlowSolver::restart() {
  State& s = *state_;
  s.triangulation = IntrinsicTriangulation(s.mesh);
  s.structure = s.input_structure;
  s.u = s.input_structure.u0;
  s.flipping = s.flips_from_start;
  s.blocked_walk.reset();
  s.flip_sequence.clear();
  s.pattern_current = false;
}

FlowResult RicciFlowSolver::solve(const TargetCurvature& target, const Eigen::VectorXd* start) {
  State& s = *state_;
  check_target(s.mesh, s.structure.geometry, target);
  s.circles.reset();
  s.goal = target;
  return s.run(start);
}

FlowResult RicciFlowSolver::solve_circle_domain(const TargetCurvature& target, int outer_loop) {
  State& s = *state_;
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
  FlowResult r = s.run(nullptr);
  s.circles.reset();
  return r;
}

FlowResult RicciFlowSolver::State::run(const Eigen::VectorXd* start) {
  State& s = *this;
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
    if (start) s.walk_to(*start);
    // With u held at some vertices, Newton converges from wherever the walk stopped, to another
    // metric than the start's: the walk is made again with flips at once.
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
        r.stalled_at_boundary = false;
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
