// One Newton (S2: Levenberg-Marquardt) step of the flow, and the reasons a flow stops.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include "flow/flow_state.h"
#include "flow/pattern_obstruction.h"
#include "ricci/mesh/errors.h"

namespace ricci {

using detail::Clock;
using detail::seconds_since;

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
bool detail::FlowState::step_direction(const Eigen::VectorXd& r, Eigen::VectorXd& du) {
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
double detail::FlowState::attainable_floor(const TargetCurvature& target) const {
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
std::string detail::FlowState::iterate(const TargetCurvature& target, int it) {
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
                                                options.loops, circles ? &*circles : nullptr);
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
  // Elsewhere only where a flip to an edge from a vertex to itself was refused (make_delaunay):
  // the stall then says nothing of the target (held-out CAD plates of genus 2 stalled so with
  // their cones, and flowed where such flips were made).
  const char* loop_note =
      "; the Delaunay triangulation of the longer steps needs an edge from a vertex to itself, "
      "which these edge flips do not make: the flow cannot go on there, whether or not the "
      "target is reachable; try the tangential scheme, whose triangles are always valid";
  // Why a stalled flow stalled, after what it did: the metric exists, the boundary's triangles
  // degenerate, a loop was refused, or `otherwise`.
  const auto stalled_because = [&](const std::string& otherwise) {
    if (exists) {
      s << exists_note;
    } else if (at_boundary) {
      s << boundary_note;
      result.stalled_at_boundary = true;
    } else if (flipping && step.blocked_by_loop) {
      s << loop_note;
      result.stalled_for_loops = true;
    } else {
      s << otherwise;
    }
    return s.str();
  };
  if (!step.accepted) {
    // A tolerance below what double precision allows here: the floor is convergence.
    result.attainable_residual = attainable_floor(target);
    if (result.attainable_residual > 0) return "";
    s << "stalled at iteration " << it << " with max |K - Kbar| = " << result.residual
      << ": no step of length >= 2^-" << options.max_step_halvings << " reduces the residual";
    if (!step.state.valid())
      s << " while keeping every triangle valid (" << detail::describe_invalid(step.state) << ")";
    return stalled_because(std::string("; the solution may not exist") +
                           (flipping ? " for this mesh" : flips_help) + ", or try another scheme");
  }
  const std::vector<double>& history = result.residual_history;
  if (stall.stalled(step, history, double_next)) {
    const int window = stall.window();
    s << "stalled at iteration " << it << ": for " << window
      << " iterations the step was cut below 1/64 to keep triangles from degenerating, and "
         "max |K - Kbar| only went from "
      << history[history.size() - static_cast<size_t>(window)] << " to " << result.residual;
    return stalled_because(std::string("; the target is not reachable") +
                           (flipping ? " even with edge flips" : flips_help) +
                           ", or try the tangential scheme, whose triangles are always valid");
  }
  if (spherical() || circles)
    lm_weight = step.alpha == 1 ? std::max(lm_weight / 4, 1e-8) : std::min(lm_weight * 8, 1e8);
  result.step_history.push_back(step.alpha);
  steps.note_step(step.alpha, step.blocked_by_validity);
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

}  // namespace ricci
