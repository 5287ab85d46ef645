#include "ricci/ricci_flow.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "ricci/delaunay.h"
#include "ricci/errors.h"
#include "ricci/hessian.h"
#include "ricci/metric.h"
#include "ricci/pattern_obstruction.h"
#include "ricci/spherical_start.h"

namespace ricci {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Kbar - K on the rows of the free vertices.
Eigen::VectorXd free_residual(const Eigen::VectorXd& k, const TargetCurvature& target,
                              const std::vector<int>& free_index, int num_free) {
  Eigen::VectorXd r(num_free);
  for (size_t v = 0; v < free_index.size(); ++v) {
    if (free_index[v] >= 0)
      r[free_index[v]] = target.curvature[static_cast<int>(v)] - k[static_cast<int>(v)];
  }
  return r;
}

// max |K - Kbar| over every vertex with a curvature target (pinned gauge vertices included).
double max_residual(const Eigen::VectorXd& k, const TargetCurvature& target) {
  double m = 0;
  for (int v = 0; v < k.size(); ++v) {
    if (!target.is_fixed(v)) m = std::max(m, std::abs(target.curvature[v] - k[v]));
  }
  return m;
}

std::string describe_invalid(const MetricState& state) {
  std::ostringstream s;
  if (state.num_invalid_edges > 0) {
    s << state.num_invalid_edges << " edges without a real length";
    if (state.num_invalid_faces > 0) s << " and ";
  }
  if (state.num_invalid_faces > 0) {
    s << state.num_invalid_faces << " triangles violating the triangle inequality (first: face "
      << state.first_invalid_face << ")";
  }
  return s.str();
}

class NewtonSolver {
 public:
  NewtonSolver(const CompactMesh& mesh, const ConformalStructure& structure,
               const TargetCurvature& target, const FlowOptions& options)
      : mesh_(mesh),
        triangulation_(options.resume && options.resume->triangulation
                           ? *options.resume->triangulation
                           : static_cast<const Triangulation&>(mesh)),
        input_structure_(structure),
        structure_(options.resume ? options.resume->structure : structure),
        target_(target),
        options_(options),
        spherical_(structure.geometry == Geometry::Spherical),
        free_index_(make_free_index()),
        assembler_(std::make_unique<HessianAssembler>(triangulation_, free_index_)),
        solver_(options.linear_solver) {}

  FlowResult run();

 private:
  std::vector<int> make_free_index() const;
  bool use_stereographic_start() const {
    return spherical_ && options_.stereographic_start && !options_.resume && mesh_.is_closed() &&
           mesh_.genus() == 0 && target_.num_fixed() == 0;
  }
  bool compute_step(const MetricState& state, const Eigen::VectorXd& r, Eigen::VectorXd& du);
  // S2, closed genus 0: moves u towards the stereographic start (spherical_start.h) with flips.
  void walk_to_stereographic_start(Eigen::VectorXd& u, MetricState& state, FlowResult& result);
  // Flips to (power) Delaunay; a changed connectivity gets a new Hessian pattern and analysis.
  void keep_delaunay(const Eigen::VectorXd& u, MetricState& state, FlowResult& result);
  void finish(FlowResult& result, const Eigen::VectorXd& u, const MetricState& state,
              const Eigen::VectorXd& k) const;

  const CompactMesh& mesh_;
  Triangulation triangulation_;                // the input's, then as flipped
  const ConformalStructure& input_structure_;  // on the input triangulation
  ConformalStructure structure_;               // eta changes with flips
  const TargetCurvature& target_;
  const FlowOptions& options_;
  const bool spherical_;
  std::vector<int> free_index_;
  std::unique_ptr<HessianAssembler> assembler_;
  LinearSolver solver_;
  SparseMatrix normal_matrix_;  // S2: H^2
  bool analyzed_ = false;
  double lm_weight_ = 1;  // S2: mu = lm_weight * |r|
  int short_steps_ = 0;   // consecutive iterations whose step was cut by invalid triangles
  FlowTimes times_;
};

std::vector<int> NewtonSolver::make_free_index() const {
  std::vector<int> index(mesh_.num_vertices(), -1);
  int n = 0;
  // E2 with no u fixed: K is invariant under u + c (scaling), so one vertex is pinned.
  const bool pin = structure_.geometry == Geometry::Euclidean && target_.num_fixed() == 0;
  for (int v = 0; v < mesh_.num_vertices(); ++v) {
    if (target_.is_fixed(v) || (pin && v == 0)) continue;
    index[v] = n++;
  }
  return index;
}

bool NewtonSolver::compute_step(const MetricState& state, const Eigen::VectorXd& r,
                                Eigen::VectorXd& du) {
  auto t = Clock::now();
  const SparseMatrix& h = assembler_->assemble(state);
  Eigen::VectorXd rhs = r;
  const SparseMatrix* system = &h;
  double shift = 0;
  if (spherical_) {
    normal_matrix_ = h * h;
    rhs = h * r;
    system = &normal_matrix_;
    shift = lm_weight_ * r.norm();
  }
  times_.assembly += seconds_since(t);
  if (!analyzed_) {
    t = Clock::now();
    solver_.analyze(*system);
    analyzed_ = true;
    times_.analysis += seconds_since(t);
  }
  t = Clock::now();
  // E2 and H2: H is positive (semi)definite; a shift only guards against round-off near
  // degenerate triangles. S2: H^2 + mu I is positive definite for mu > 0.
  double max_diag = 0;
  for (int i = 0; i < system->rows(); ++i)
    max_diag = std::max(max_diag, std::abs(system->coeff(i, i)));
  bool ok = solver_.factorize(*system, shift);
  for (double extra = 1e-12 * std::max(max_diag, 1e-300); !ok && extra < 1e3 * max_diag;
       extra *= 10) {
    ok = solver_.factorize(*system, shift + extra);
  }
  times_.factorization += seconds_since(t);
  if (!ok) return false;
  t = Clock::now();
  du = solver_.solve(rhs);
  times_.solve += seconds_since(t);
  return du.allFinite();
}

void NewtonSolver::finish(FlowResult& result, const Eigen::VectorXd& u, const MetricState& state,
                          const Eigen::VectorXd& k) const {
  const Geometry g = structure_.geometry;
  result.u = u;
  result.curvature = k;
  result.edge_lengths = state.lengths();
  result.area = state.valid() ? total_area(triangulation_, g, state)
                              : std::numeric_limits<double>::quiet_NaN();
  result.radius.resize(u.size());
  result.target.resize(u.size());
  for (int v = 0; v < u.size(); ++v) {
    result.radius[v] = radius_from_conformal_factor(g, u[v]);
    result.target[v] =
        target_.is_fixed(v) ? std::numeric_limits<double>::quiet_NaN() : target_.curvature[v];
  }
  if (result.num_flips > 0 || (options_.resume && options_.resume->triangulation)) {
    result.triangulation = triangulation_;
  }
  result.structure = structure_;
  result.structure.u0 = u;
  result.num_analyses = solver_.num_analyses();
  result.num_factorizations = solver_.num_factorizations();
  result.times = times_;
}

void NewtonSolver::walk_to_stereographic_start(Eigen::VectorXd& u, MetricState& state,
                                               FlowResult& result) {
  Eigen::VectorXd lifted;
  try {
    lifted = stereographic_start(mesh_, input_structure_);
  } catch (const Error&) {
    return;  // the direct flow may still converge
  }
  if (!lifted.allFinite()) return;
  // The lifted u need not give valid triangles on the current triangulation: walk there in the
  // longest valid steps, flipping to Delaunay after each (Ptolemy keeps the conformal class).
  for (int step = 0; step < 200; ++step) {
    const Eigen::VectorXd d = lifted - u;
    double alpha = 1;
    MetricState trial;
    for (; alpha > 1e-6; alpha *= 0.5) {
      trial = evaluate_metric(triangulation_, structure_, u + alpha * d);
      if (trial.valid()) break;
    }
    if (!trial.valid()) return;
    u += alpha * d;
    state = std::move(trial);
    keep_delaunay(u, state, result);
    if (alpha == 1) return;
  }
}

void NewtonSolver::keep_delaunay(const Eigen::VectorXd& u, MetricState& state, FlowResult& result) {
  if (!options_.edge_flips) return;
  const auto t = Clock::now();
  const FlipReport flips =
      make_delaunay(triangulation_, structure_, u, state, 10 * mesh_.num_edges());
  result.num_flips += flips.flips;
  result.flip_sequence.insert(result.flip_sequence.end(), flips.sequence.begin(),
                              flips.sequence.end());
  if (flips.flips > 0) {
    ++result.connectivity_changes;
    assembler_ = std::make_unique<HessianAssembler>(triangulation_, free_index_);
    analyzed_ = false;
  }
  times_.flips += seconds_since(t);
}

FlowResult NewtonSolver::run() {
  const auto start = Clock::now();
  FlowResult result;
  if (options_.resume) result.flip_sequence = options_.resume->flip_sequence;
  const int n = assembler_->num_free();
  Eigen::VectorXd u = structure_.u0;
  MetricState state = evaluate_metric(triangulation_, structure_, u);
  times_.setup = seconds_since(start);
  if (!state.valid()) {
    result.failure = "the initial metric of this scheme is not valid in " +
                     to_string(structure_.geometry) + " geometry: " + describe_invalid(state) +
                     "; try another scheme (tangential packing is always valid)";
    finish(result, u, state, Eigen::VectorXd::Constant(u.size(), std::nan("")));
    result.times.total = seconds_since(start);
    return result;
  }
  if (const std::string obstruction =
          circle_pattern_obstruction(triangulation_, structure_, target_);
      !obstruction.empty()) {
    result.failure = obstruction;
    finish(result, u, state, curvature(triangulation_, state));
    result.times.total = seconds_since(start);
    return result;
  }
  keep_delaunay(u, state, result);
  if (use_stereographic_start()) walk_to_stereographic_start(u, state, result);
  Eigen::VectorXd k = curvature(triangulation_, state);
  for (int it = 0;; ++it) {
    result.residual = max_residual(k, target_);
    result.residual_history.push_back(result.residual);
    result.iterations = it;
    if (options_.progress && !options_.progress({it, result.residual})) {
      result.failure = "cancelled at iteration " + std::to_string(it);
      break;
    }
    if (result.residual <= options_.tolerance || n == 0) {
      result.converged = true;
      break;
    }
    if (it >= options_.max_iterations) {
      std::ostringstream s;
      s << "no convergence in " << it << " iterations: max |K - Kbar| = " << result.residual
        << " > tolerance " << options_.tolerance
        << "; raise the iteration limit, or loosen the tolerance";
      result.failure = s.str();
      break;
    }
    const Eigen::VectorXd r = free_residual(k, target_, free_index_, n);
    Eigen::VectorXd du;
    if (!compute_step(state, r, du)) {
      std::ostringstream s;
      s << "the Hessian could not be factorized at iteration " << it
        << " (max |K - Kbar| = " << result.residual << "); the metric is close to degenerate";
      result.failure = s.str();
      break;
    }
    // Backtracking on phi = |Kbar - K|^2 / 2 (Armijo), staying where every triangle is valid.
    const auto t = Clock::now();
    const double phi = 0.5 * r.squaredNorm();
    double alpha = 1;
    bool accepted = false;
    bool blocked_by_validity = false;  // a longer step left the valid set
    MetricState trial_state;
    Eigen::VectorXd trial_u = u;
    Eigen::VectorXd trial_k;
    for (int halving = 0; halving <= options_.max_step_halvings; ++halving, alpha *= 0.5) {
      for (int v = 0; v < u.size(); ++v) {
        if (free_index_[v] >= 0) trial_u[v] = u[v] + alpha * du[free_index_[v]];
      }
      trial_state = evaluate_metric(triangulation_, structure_, trial_u);
      if (!trial_state.valid()) {
        blocked_by_validity = true;
        continue;
      }
      trial_k = curvature(triangulation_, trial_state);
      const double trial_phi = 0.5 * free_residual(trial_k, target_, free_index_, n).squaredNorm();
      if (trial_phi <= (1 - 1e-4 * alpha) * phi) {
        accepted = true;
        break;
      }
    }
    times_.line_search += seconds_since(t);
    if (!accepted) {
      std::ostringstream s;
      s << "stalled at iteration " << it << " with max |K - Kbar| = " << result.residual
        << ": no step of length >= 2^-" << options_.max_step_halvings << " reduces the residual";
      if (!trial_state.valid())
        s << " while keeping every triangle valid (" << describe_invalid(trial_state) << ")";
      s << (options_.edge_flips ? "; the solution may not exist for this mesh"
                                : "; the solution may not exist on this triangulation (edge "
                                  "flips help)")
        << ", or try another scheme";
      result.failure = s.str();
      break;
    }
    // Steps cut short by degenerating triangles for many iterations with little progress:
    // the flow is running into the boundary of the valid set, where no solution lies.
    constexpr int kStallWindow = 10;
    short_steps_ = (blocked_by_validity && alpha <= 1.0 / 64) ? short_steps_ + 1 : 0;
    if (short_steps_ >= kStallWindow &&
        result.residual >
            0.5 * result.residual_history[result.residual_history.size() - kStallWindow]) {
      std::ostringstream s;
      s << "stalled at iteration " << it << ": for " << kStallWindow
        << " iterations the step was cut below 1/64 to keep triangles from degenerating, and "
           "max |K - Kbar| only went from "
        << result.residual_history[result.residual_history.size() - kStallWindow] << " to "
        << result.residual
        << (options_.edge_flips ? "; the target is not reachable even with edge flips"
                                : "; the target is not reachable on this triangulation (edge "
                                  "flips help)")
        << ", or try the tangential scheme, whose triangles are always valid";
      result.failure = s.str();
      break;
    }
    if (spherical_)
      lm_weight_ = alpha == 1 ? std::max(lm_weight_ / 4, 1e-8) : std::min(lm_weight_ * 8, 1e8);
    result.step_history.push_back(alpha);
    u = trial_u;
    state = std::move(trial_state);
    const int flips_before = result.num_flips;
    keep_delaunay(u, state, result);
    k = result.num_flips > flips_before ? curvature(triangulation_, state) : std::move(trial_k);
  }
  // E2 without fixed vertices: choose the scale of the input's total area.
  if (result.converged && structure_.geometry == Geometry::Euclidean && target_.num_fixed() == 0) {
    const double c =
        0.5 * std::log(mesh_.input_area() / total_area(triangulation_, Geometry::Euclidean, state));
    u.array() += c;
    state = evaluate_metric(triangulation_, structure_, u);
    k = curvature(triangulation_, state);
    result.residual = max_residual(k, target_);
  }
  finish(result, u, state, k);
  result.times.total = seconds_since(start);
  return result;
}

}  // namespace

double initial_length_scale(const CompactMesh& mesh, Geometry geometry,
                            const TargetCurvature& target) {
  if (geometry == Geometry::Euclidean) return 1;
  double area = gauss_bonnet_area(mesh, geometry, target);
  if (!(area > 0)) area = 1;
  double scale = std::sqrt(area / mesh.input_area());
  if (geometry == Geometry::Spherical) {
    double max_perimeter = 0;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      double p = 0;
      for (int c = 0; c < 3; ++c) p += mesh.input_lengths()[mesh.face_edge(f, c)];
      max_perimeter = std::max(max_perimeter, p);
    }
    scale = std::min(scale, 3.14159265358979323846 / max_perimeter);
  }
  return scale;
}

ConformalStructure prepare_flow(const CompactMesh& mesh, Geometry geometry,
                                const SchemeOptions& scheme, const TargetCurvature& target) {
  check_target(mesh, geometry, target);
  return initialize_scheme(mesh, geometry, scheme, initial_length_scale(mesh, geometry, target));
}

FlowResult run_ricci_flow(const CompactMesh& mesh, const ConformalStructure& structure,
                          const TargetCurvature& target, const FlowOptions& options) {
  check_target(mesh, structure.geometry, target);
  if (!(options.tolerance > 0) || options.max_iterations < 0) {
    throw InvalidArgumentError(
        "ricci flow: tolerance must be positive and the iteration limit "
        "non-negative");
  }
  const int nv = mesh.num_vertices();
  if (static_cast<int>(structure.eps.size()) != nv || structure.u0.size() != nv ||
      static_cast<int>(structure.eta.size()) != mesh.num_edges()) {
    throw InvalidArgumentError("ricci flow: the conformal structure was built for another mesh");
  }
  if (const FlowResult* r = options.resume) {
    if (r->u.size() != nv || static_cast<int>(r->structure.eta.size()) != mesh.num_edges() ||
        r->structure.geometry != structure.geometry ||
        (r->triangulation && r->triangulation->num_vertices() != nv)) {
      throw InvalidArgumentError(
          "ricci flow: the result to resume from belongs to another mesh "
          "or geometry");
    }
  }
  NewtonSolver solver(mesh, structure, target, options);
  return solver.run();
}

FlowResult compute_ricci_flow(const CompactMesh& mesh, Geometry geometry,
                              const SchemeOptions& scheme, const TargetCurvature& target,
                              const FlowOptions& options) {
  const ConformalStructure structure = prepare_flow(mesh, geometry, scheme, target);
  FlowResult result = run_ricci_flow(mesh, structure, target, options);
  if (!result.converged) {
    throw ConvergenceError("ricci flow (" + to_string(geometry) + ", " + to_string(scheme.scheme) +
                               "): " + result.failure,
                           result.iterations, result.residual);
  }
  return result;
}

}  // namespace ricci
