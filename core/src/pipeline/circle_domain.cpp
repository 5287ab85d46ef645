#include "pipeline/circle_domain.h"

#include <cmath>
#include <complex>
#include <sstream>

#include <Eigen/Dense>

#include "ricci/mesh/errors.h"

namespace ricci::detail {

namespace {

// Anderson acceleration of the fixed-point iteration x -> g(x) on the boundary curvature: the
// next x is the combination of the last few g values whose residuals g - x cancel best.
class AndersonMixing {
 public:
  explicit AndersonMixing(int depth) : depth_(depth) {}

  Eigen::VectorXd next(const Eigen::VectorXd& x, const Eigen::VectorXd& g) {
    const Eigen::VectorXd f = g - x;
    if (has_last_) {
      df_.push_back(f - last_f_);
      dg_.push_back(g - last_g_);
      if (static_cast<int>(df_.size()) > depth_) df_.erase(df_.begin()), dg_.erase(dg_.begin());
    }
    last_f_ = f, last_g_ = g, has_last_ = true;
    if (df_.empty()) return g;
    Eigen::MatrixXd a(f.size(), static_cast<long>(df_.size()));
    for (size_t k = 0; k < df_.size(); ++k) a.col(static_cast<long>(k)) = df_[k];
    const Eigen::VectorXd gamma = a.colPivHouseholderQr().solve(f);
    Eigen::VectorXd result = g;
    for (size_t k = 0; k < dg_.size(); ++k) result -= gamma[static_cast<long>(k)] * dg_[k];
    return result;
  }
  void reset() { df_.clear(), dg_.clear(), has_last_ = false; }

 private:
  int depth_;
  std::vector<Eigen::VectorXd> df_, dg_;
  Eigen::VectorXd last_f_, last_g_;
  bool has_last_ = false;
};

}  // namespace

BoundaryRefit refit_on_mesh(const CompactMesh& mesh, int outer_loop) {
  return [&mesh, outer_loop](const FlowResult& r) {
    return circle_boundary_target(result_triangulation(mesh, r), r.edge_lengths, outer_loop);
  };
}

bool reach_circle_domain(RicciFlowSolver& solver, const CompactMesh& mesh, int outer_loop,
                         const TargetCurvature& target, const UniformizationOptions& o,
                         bool one_solve, const OnDouble& on_double, Uniformization& run) {
  const BoundaryRefit refit = refit_on_mesh(mesh, outer_loop);
  if (one_solve) {
    // Where the double follows a stall at the boundary's triangles, the one solve stops sooner
    // there (StallWindow); the repeated flows on the surface do not (they can go on past it).
    const auto one = [&] {
      solver.double_next(on_double.follows);
      run.result = solver.solve_circle_domain(target, outer_loop);
      solver.double_next(false);
      run.totals.add(run.result);
      if (run.result.converged) run.boundary_change = 0;  // the circles' target at the result
      return run.result.converged || run.result.stop == FlowStop::Cancelled;
    };
    // Flips when needed: first everything the input's triangulation allows (the one solve, then
    // the repeated flows, as without flips), then the one solve with flips from the start (as
    // with them always). A one solve that stops for flips lets the flows' fixed point, which
    // keeps each boundary target fixed, try without. Where a one solve with flips stalls at the
    // boundary's triangles, the flow on the double, which flips boundary edges, comes before the
    // repeated flows on the surface: those ran into such triangles too on FreeSurfer's flat patch
    // of a hemisphere (2.5 s for nothing), but reach the circle domain of OpenFOAM's text annulus,
    // whose double's flows do not settle.
    solver.defer_flips(true);
    const bool done = one();
    const bool flips_needed = run.result.stop == FlowStop::FlipsNeeded;
    const std::string one_failure = run.result.failure;
    solver.defer_flips(false);
    if (done) return true;
    if (!flips_needed && on_double.flow && on_double.flow()) return false;  // flips from the start
    solver.restart();
    if (flips_needed) {
      solver.defer_flips(true);
      fit_boundary_to_circles(solver, mesh, refit, target, o, run);
      solver.defer_flips(false);
      if (run.result.converged || run.result.stop == FlowStop::Cancelled) return false;
      const std::string why =
          "the one solve: " + one_failure + "; the repeated flows: " + run.result.failure;
      solver.restart_with_flips(why);
      if (one()) return true;
      if (on_double.flow && on_double.flow()) return false;
      solver.restart_with_flips(why);
    }
  }
  fit_boundary_to_circles(solver, mesh, refit, target, o, run);
  if (!run.result.converged && !run.double_failure.empty()) {
    run.result.failure += "; " + run.double_failure;
  }
  return false;
}

void fit_boundary_to_circles(RicciFlowSolver& solver, const CompactMesh& mesh,
                             const BoundaryRefit& refit, TargetCurvature target,
                             const UniformizationOptions& o, Uniformization& out) {
  AndersonMixing mixing(5);
  TargetCurvature plain = target;  // the last plain iterate, g(x)
  bool warm = false;               // this flow starts from the last converged one
  double least_change = INFINITY;  // the boundary curvature's, and at which flow
  int least_at = 0;
  for (int flows = 1;; ++flows) {
    out.result = solver.solve(target);
    out.totals.add(out.result);
    if (!out.result.converged) {
      // Retry once with the plain iterate from a cold start; give up when that failed.
      if (target.curvature == plain.curvature && !warm) break;
      mixing.reset();
      target = plain;
      solver.restart();
      warm = false;
      continue;
    }
    const TargetCurvature next = refit(out.result);
    out.boundary_change = (next.curvature - target.curvature).cwiseAbs().maxCoeff();
    if (out.boundary_change <= o.boundary_tolerance) break;
    if (out.boundary_change < least_change) least_change = out.boundary_change, least_at = flows;
    const bool stuck = flows - least_at >= kUnsettledFlows;
    if (flows >= o.max_boundary_iterations || stuck) {
      std::ostringstream s;
      s << "the boundary curvature still changed by " << out.boundary_change << " after " << flows
        << " flows (tolerance " << o.boundary_tolerance << ")";
      if (stuck) {
        s << ": it has not changed less than at flow " << least_at << " (" << least_change
          << ") in the " << kUnsettledFlows << " flows since, so the boundary no longer settles";
      } else {
        s << "; raise the boundary iteration limit";
      }
      out.result.converged = false;
      out.result.stop = FlowStop::IterationLimit;
      out.result.failure = s.str();
      break;
    }
    plain = next;
    warm = true;
    target.curvature = mixing.next(target.curvature, next.curvature);
    try {
      check_target(mesh, Geometry::Euclidean, target);
    } catch (const InvalidTargetError&) {
      mixing.reset();
      target = plain;
    }
  }
}

std::pair<Eigen::Vector2d, double> fit_circle(const std::vector<Eigen::Vector3d>& points,
                                              const std::vector<int>& which) {
  Eigen::MatrixXd a(which.size(), 3);
  Eigen::VectorXd b(which.size());
  for (size_t i = 0; i < which.size(); ++i) {
    const Eigen::Vector3d& p = points[which[i]];
    a.row(static_cast<long>(i)) << p.x(), p.y(), 1.0;
    b[static_cast<long>(i)] = -(p.x() * p.x() + p.y() * p.y());
  }
  const Eigen::Vector3d d = a.colPivHouseholderQr().solve(b);
  const Eigen::Vector2d center(-d[0] / 2, -d[1] / 2);
  return {center, std::sqrt(std::max(0.0, center.squaredNorm() - d[2]))};
}

double circle_error(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh) {
  double error = 0;
  for (const auto& loop : mesh.boundary_loops()) {
    const auto [center, radius] = fit_circle(points, loop);
    for (int v : loop) {
      error = std::max(error, std::abs((points[v].head<2>() - center).norm() - radius) / radius);
    }
  }
  return error;
}

std::vector<Eigen::Vector3d> normalize_to_unit_disk(std::vector<Eigen::Vector3d> points,
                                                    const std::vector<int>& boundary, int center,
                                                    int axis) {
  using Complex = std::complex<double>;
  const auto [c, r] = fit_circle(points, boundary);
  for (auto& p : points) p = Eigen::Vector3d((p.x() - c.x()) / r, (p.y() - c.y()) / r, 0.0);
  if (center >= 0) {
    const Complex a(points[center].x(), points[center].y());
    if (!(std::abs(a) < 1 - 1e-12)) {
      throw InvalidArgumentError("the center vertex " + std::to_string(center) +
                                 " is on the unit circle; choose an interior vertex");
    }
    for (auto& p : points) {
      const Complex z(p.x(), p.y());
      const Complex w = (z - a) / (1.0 - std::conj(a) * z);
      p = Eigen::Vector3d(w.real(), w.imag(), 0.0);
    }
  }
  if (axis >= 0) {
    const Complex z(points[axis].x(), points[axis].y());
    if (!(std::abs(z) > 1e-12)) {
      throw InvalidArgumentError("the axis vertex " + std::to_string(axis) +
                                 " maps to the centre, so it fixes no direction; choose another");
    }
    const Complex turn = std::conj(z) / std::abs(z);
    for (auto& p : points) {
      const Complex w = turn * Complex(p.x(), p.y());
      p = Eigen::Vector3d(w.real(), w.imag(), 0.0);
    }
  }
  return points;
}

}  // namespace ricci::detail
