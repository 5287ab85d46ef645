#include "flow/flow_steps.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <sstream>

namespace ricci::detail {

Eigen::VectorXd free_residual(const Eigen::VectorXd& k, const TargetCurvature& target,
                              const std::vector<int>& free_index, int num_free) {
  Eigen::VectorXd r(num_free);
  for (size_t v = 0; v < free_index.size(); ++v) {
    if (free_index[v] >= 0)
      r[free_index[v]] = target.curvature[static_cast<int>(v)] - k[static_cast<int>(v)];
  }
  return r;
}

double forcing_term(const Eigen::VectorXd& r, double tolerance) {
  const double size = max_abs(r);
  if (!(size > 0)) return 0.1;
  return std::clamp(std::max(size, 0.1 * tolerance / size), 1e-12, 0.1);
}

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

std::vector<int> free_vertex_index(int num_vertices, Geometry geometry,
                                   const TargetCurvature& target) {
  std::vector<int> index(num_vertices, -1);
  int n = 0;
  const bool pin = geometry == Geometry::Euclidean && target.num_fixed() == 0;
  for (int v = 0; v < num_vertices; ++v) {
    if (target.is_fixed(v) || (pin && v == 0)) continue;
    index[v] = n++;
  }
  return index;
}

// === The step direction

void StepSolver::set_pattern(const Triangulation& mesh, const std::vector<int>& free_index,
                             bool unflipped) {
  // The assembler (its pattern) is built when a step first needs H: the walk to a start changes
  // the connectivity at most of its steps and solves none (tr12j's atlas: 33 changes, 6 analyses).
  assembler_.reset();
  mesh_ = &mesh;
  // The last ordering's rows are other vertices' under another free set.
  if (free_index != free_index_) last_order_.clear();
  free_index_ = free_index;
  num_free_ = static_cast<int>(
      std::count_if(free_index_.begin(), free_index_.end(), [](int i) { return i >= 0; }));
  unflipped_ = unflipped;
  analyzed_ = false;
  normal_pattern_ = false;
  held_ = Held::None;
  krylov_rate_ = 0;
  stale_fell_short_ = false;
}

HessianAssembler& StepSolver::assembler() {
  if (!assembler_) assembler_ = std::make_unique<HessianAssembler>(*mesh_, free_index_);
  return *assembler_;
}

std::vector<int> StepSolver::rows_in_order() const {
  if (!unflipped_ || order_.empty() || num_free() < kNestedDissectionRows) return {};
  return order_.rows(free_index_);
}

void StepSolver::begin_solve() {
  held_ = Held::None;
  step_reuses_factor_ = false;
}

bool StepSolver::factorize(const MetricState& state, const Eigen::VectorXd& r, bool spherical,
                           double lm_weight, Eigen::VectorXd& rhs, FlowTimes& times,
                           bool assembled) {
  auto t = Clock::now();
  const SparseMatrix& h = assembled ? assembler().matrix() : assembler().assemble(state);
  rhs = r;
  const SparseMatrix* system = &h;
  double shift = 0;
  if (spherical) {
    square_symmetric(h, normal_matrix_, normal_pattern_);
    normal_pattern_ = true;
    rhs = h * r;
    system = &normal_matrix_;
    shift = lm_weight * r.norm();
  }
  times.assembly += seconds_since(t);
  if (!analyzed_) {
    t = Clock::now();
    const std::vector<int> rows = spherical ? std::vector<int>() : rows_in_order();
    // Flips change a few edges of the pattern between two analyses: the last ordering, kept while
    // its fill stays within kReusedOrderFill of the last one found afresh, spares the ordering
    // (the bull's atlas at 8 cones: 5 analyses, 0.03 s to 0.015 s; its fill 6 % more).
    const bool cholmod = solver_.kind() == LinearSolverKind::Cholmod;
    bool reused = false;
    if (cholmod && rows.empty() && !spherical &&
        static_cast<long>(last_order_.size()) == system->rows()) {
      solver_.analyze(*system, &last_order_);
      reused = static_cast<double>(solver_.factor_entries()) <=
               kReusedOrderFill * static_cast<double>(fresh_fill_);
    }
    if (!reused) {
      solver_.analyze(*system, rows.empty() ? nullptr : &rows);
      if (cholmod) fresh_fill_ = solver_.factor_entries();
    }
    if (cholmod && !spherical) last_order_ = solver_.ordering();
    analyzed_ = true;
    times.analysis += seconds_since(t);
  }
  t = Clock::now();
  krylov_rate_ = 0;
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
  times.factorization += seconds_since(t);
  return ok;
}

template <class Apply>
MinresResult StepSolver::precondition_with_factor(const Apply& apply, const Eigen::VectorXd& r,
                                                  double rtol, int max_iterations,
                                                  Eigen::VectorXd& du, FlowTimes& times) {
  const auto t = Clock::now();
  MinresResult m = minres(
      apply, [&](const Eigen::VectorXd& x) { return solver_.precondition(x); }, r, rtol,
      max_iterations);
  times.solve += seconds_since(t);
  krylov_iterations_ += m.iterations;
  note_rate(m);
  du = std::move(m.x);
  return m;
}

bool StepSolver::reuse_factor(Held kind, double rtol, int max_iterations) const {
  if (held_ != kind) return false;
  if (!(krylov_rate_ > 0)) return true;
  return krylov_rate_ < 1 && std::log(rtol) / std::log(krylov_rate_) <= max_iterations;
}

void StepSolver::note_rate(const MinresResult& m) {
  krylov_rate_ = m.iterations > 0 && m.relative_residual > 0
                     ? std::pow(m.relative_residual, 1.0 / m.iterations)
                     : 0;
}

bool StepSolver::solve(const MetricState& state, const Eigen::VectorXd& r, bool spherical,
                       double lm_weight, double rtol, Eigen::VectorXd& du, FlowTimes& times) {
  const double size = max_abs(r);
  const Held kind = spherical ? Held::Normal : Held::Hessian;
  // Near the solution H changes little from one step to the next: the factorization of an earlier
  // step's system preconditions the current one to within a few MINRES iterations, each a solve
  // with that factor in single precision (a twentieth of a factorization or less). After a
  // factorization whose first reuse fell short, the next is tried only once the residual has
  // fallen well below the one it was made at.
  bool assembled = false;
  if (step_reuses_factor_ && reuse_factor(kind, rtol, kStaleSolveIterations) &&
      (!stale_fell_short_ || krylov_rate_ > 0 ||
       size <= kReuseFactorBelowResidual * factor_residual_)) {
    assembled = true;
    auto t = Clock::now();
    const SparseMatrix& h = assembler().assemble(state);
    times.assembly += seconds_since(t);
    // S2: the Levenberg-Marquardt system (H^2 + mu I) du = H r, with H^2 applied, not formed.
    const double mu = spherical ? lm_weight * r.norm() : 0;
    const Eigen::VectorXd rhs = spherical ? Eigen::VectorXd(h * r) : r;
    const auto apply = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
      if (!spherical) return h * x;
      return h * (h * x) + mu * x;
    };
    const MinresResult m =
        precondition_with_factor(apply, rhs, rtol, kStaleSolveIterations, du, times);
    // MINRES measures its residual in the factor's norm; the line search needs |r|^2 to fall
    // along du, which |r - H du| < |r| guarantees (|r - H du| <= rtol |r| with rtol < 1 in E2
    // and H2, where the system is H du = r).
    const double linearized = du.allFinite() ? (r - h * du).norm() : r.norm();
    stale_fell_short_ = !(m.relative_residual <= rtol && linearized < r.norm() &&
                          (spherical || linearized <= rtol * r.norm()));
    if (!stale_fell_short_) return true;
  }
  Eigen::VectorXd rhs;
  held_ = Held::None;
  if (!factorize(state, r, spherical, lm_weight, rhs, times, assembled)) return false;
  held_ = kind;
  factor_residual_ = size;
  const auto t = Clock::now();
  du = solver_.solve(rhs);
  times.solve += seconds_since(t);
  return du.allFinite();
}

StepSolver::Krylov StepSolver::solve_coupled(const MetricState& state, const Eigen::VectorXd& r,
                                             const Coupling& coupling, double damping, double rtol,
                                             Eigen::VectorXd& du, FlowTimes& times) {
  const SparseMatrix& h = assembler().matrix();
  const auto damped = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
    return (1 + damping) * (h * x) - coupling(x);
  };
  // The last factorization, of an earlier H on this pattern, as the preconditioner while it keeps
  // MINRES short: a factorization costs as much as some ten solves with it.
  Krylov out;
  const bool assembled = reuse_factor(Held::Hessian, rtol, kReuseFactorBelow);
  if (assembled) {
    const auto t = Clock::now();
    assembler().assemble(state);
    times.assembly += seconds_since(t);
    const MinresResult m =
        precondition_with_factor(damped, r, rtol, kStaleKrylovIterations, du, times);
    if (du.allFinite() && m.relative_residual <= rtol) {
      out.progress = true;
      return out;
    }
  }
  Eigen::VectorXd rhs;
  held_ = Held::None;
  out.factorized = factorize(state, r, false, 0, rhs, times, assembled);
  if (!out.factorized) return out;
  held_ = Held::Hessian;
  factor_residual_ = max_abs(r);
  const MinresResult m = precondition_with_factor(damped, r, rtol, kMaxKrylovIterations, du, times);
  out.progress = du.allFinite() && m.relative_residual < 1;
  return out;
}

// === The line search

namespace {

bool invalid_at_boundary(const Triangulation& mesh, const MetricState& state) {
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (state.faces[f].valid) continue;
    for (int e : mesh.face_edges(f)) {
      if (mesh.is_boundary_edge(e)) return true;
    }
  }
  return false;
}

}  // namespace

void evaluate_trial_point(const IntrinsicTriangulation& mesh, const ConformalStructure& structure,
                          const Eigen::VectorXd& u, bool flip_invalid, bool loops, LineSearch& s) {
  s.state = evaluate_metric(mesh, structure, u);
  s.flipped.reset();
  s.flips = FlipReport();
  if (!s.state.valid() && flip_invalid && all_ptolemy(structure)) {
    s.flipped.emplace(mesh);
    ConformalStructure flipped_structure = structure;
    s.flips =
        make_delaunay(*s.flipped, flipped_structure, u, s.state, 10 * mesh.num_edges(), loops);
    s.flipped_eta = std::move(flipped_structure.eta);
  }
}

LineSearch search_line(const IntrinsicTriangulation& mesh, const ConformalStructure& structure,
                       const TargetCurvature& target, const std::vector<int>& free_index,
                       const Eigen::VectorXd& u, const Eigen::VectorXd& du, double phi,
                       int max_halvings, bool flip_invalid, bool loops,
                       const CircleCondition* circles) {
  LineSearch s;
  s.u = u;
  const int n = static_cast<int>(du.size());
  for (int halving = 0; halving <= max_halvings; ++halving, s.alpha *= 0.5) {
    for (int v = 0; v < u.size(); ++v) {
      if (free_index[v] >= 0) s.u[v] = u[v] + s.alpha * du[free_index[v]];
    }
    evaluate_trial_point(mesh, structure, s.u, flip_invalid, loops, s);
    if (!s.state.valid()) {
      s.blocked_by_validity = true;
      const bool at_boundary = invalid_at_boundary(s.flipped ? *s.flipped : mesh, s.state);
      s.blocked_at_boundary = s.blocked_at_boundary || at_boundary;
      s.blocked_at_boundary_after_flips =
          s.blocked_at_boundary_after_flips || (at_boundary && s.flipped);
      s.blocked_by_loop = s.blocked_by_loop || s.flips.loops_refused > 0;
      continue;
    }
    s.k = curvature(s.flipped ? *s.flipped : mesh, s.state);
    const TargetCurvature* trial_target = &target;
    TargetCurvature moved;
    if (circles) {
      moved = target;
      circles->set_target(s.state.lengths(), moved);
      trial_target = &moved;
    }
    const double trial_phi = 0.5 * free_residual(s.k, *trial_target, free_index, n).squaredNorm();
    if (trial_phi <= (1 - 1e-4 * s.alpha) * phi) {
      s.accepted = true;
      break;
    }
  }
  return s;
}

bool StallWindow::stalled(const LineSearch& step, const std::vector<double>& residual_history,
                          bool double_next) {
  short_steps_ = (step.blocked_by_validity && step.alpha <= kShortStep) ? short_steps_ + 1 : 0;
  loop_steps_ = (step.blocked_by_loop && step.alpha <= kShortStep) ? loop_steps_ + 1 : 0;
  boundary_steps_ =
      (step.blocked_at_boundary_after_flips && step.alpha <= kShortStep) ? boundary_steps_ + 1 : 0;
  recent_.push_back(step.blocked_by_validity ? -step.alpha : step.alpha);
  if (recent_.size() > 6) recent_.erase(recent_.begin());
  const size_t n = residual_history.size();
  const auto progress_below = [&](int window, double factor) {
    return residual_history[n - 1] > factor * residual_history[n - static_cast<size_t>(window)];
  };
  const bool unmendable =
      (loop_steps_ >= kLoopLength && progress_below(kLoopLength, 0.5)) ||
      (double_next && boundary_steps_ >= kLoopLength && progress_below(kLoopLength, 0.9));
  window_ = unmendable                                                ? kLoopLength
            : short_steps_ >= kLength && progress_below(kLength, 0.5) ? kLength
                                                                      : 0;
  return window_ > 0;
}

std::string StallWindow::flips_called_for() const {
  std::ostringstream s;
  if (short_steps_ >= kLengthBeforeFlips) {
    s << short_steps_ << " steps in a row were cut to at most 1/64 to keep triangles valid";
    return s.str();
  }
  const auto cut = [](double step) { return step < 0 ? -step : 2.0; };  // 2: not cut by triangles
  const size_t n = recent_.size();
  if (n >= 3 && cut(recent_[n - 3]) <= 0.0625 && cut(recent_[n - 2]) <= cut(recent_[n - 3]) &&
      cut(recent_[n - 1]) <= cut(recent_[n - 2])) {
    s << "three steps in a row were cut ever shorter (" << cut(recent_[n - 3]) << ", "
      << cut(recent_[n - 2]) << ", " << cut(recent_[n - 1]) << ") to keep triangles valid";
    return s.str();
  }
  int bounces = 0;
  for (size_t i = 1; i < n; ++i) bounces += recent_[i - 1] == 1 && cut(recent_[i]) <= 0.25;
  if (bounces >= 2) {
    s << "within " << n << " steps, full steps were followed " << bounces
      << " times by steps cut to at most 1/4 to keep triangles valid";
  }
  return s.str();
}

}  // namespace ricci::detail
