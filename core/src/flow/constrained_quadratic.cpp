#include "flow/constrained_quadratic.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/LU>

namespace ricci {

Eigen::VectorXd minimize_constrained(const ConstrainedQuadratic& p, const Eigen::VectorXd& start) {
  const long n = start.size(), rows = p.a.rows();
  Eigen::VectorXd x = start;
  std::vector<long> working;
  std::vector<char> in_working(static_cast<size_t>(rows), 0);
  const double scale = std::max(1.0, start.cwiseAbs().maxCoeff());
  // Every step either adds a constraint (at most n in a row) or drops one, after which f falls
  // strictly: a few times n + rows steps end it.
  for (long step = 0; step < 4 * (n + rows) + 10; ++step) {
    const long w = static_cast<long>(working.size()), extra = p.sum_fixed ? 1 : 0;
    const long size = n + w + extra;
    const Eigen::VectorXd gradient = p.q * x + p.b;
    // q d + a_W^T lambda + mu 1 = -gradient, a_W d = 0, sum d = 0.
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(size, size);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(size);
    kkt.topLeftCorner(n, n) = p.q;
    rhs.head(n) = -gradient;
    for (long j = 0; j < w; ++j) {
      kkt.block(n + j, 0, 1, n) = p.a.row(working[static_cast<size_t>(j)]);
      kkt.block(0, n + j, n, 1) = p.a.row(working[static_cast<size_t>(j)]).transpose();
    }
    if (p.sum_fixed) {
      kkt.block(n + w, 0, 1, n).setOnes();
      kkt.block(0, n + w, n, 1).setOnes();
    }
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(kkt);
    if (!(lu.rcond() > 1e-14)) return start;
    const Eigen::VectorXd solved = lu.solve(rhs);
    if (!solved.allFinite()) return start;
    const Eigen::VectorXd d = solved.head(n);
    if (d.cwiseAbs().maxCoeff() <= 1e-12 * scale) {
      // Stationary with the working set held: drop the constraint whose multiplier says f falls
      // off it, most; none: the minimizer.
      long drop = -1;
      double most = -1e-12 * std::max(1.0, gradient.cwiseAbs().maxCoeff());
      for (long j = 0; j < w; ++j) {
        if (solved[n + j] < most) most = solved[n + j], drop = j;
      }
      if (drop < 0) break;
      in_working[static_cast<size_t>(working[static_cast<size_t>(drop)])] = 0;
      working.erase(working.begin() + drop);
      continue;
    }
    double length = 1;
    long blocking = -1;
    const Eigen::VectorXd ad = p.a * d, ax = p.a * x;
    const double length_d = d.norm();
    for (long i = 0; i < rows; ++i) {
      // A row the step runs along (within rounding) does not block it.
      if (in_working[static_cast<size_t>(i)] || !(ad[i] > 1e-12 * p.a.row(i).norm() * length_d)) {
        continue;
      }
      const double reach = std::max(0.0, (p.limit[i] - ax[i]) / ad[i]);
      if (reach < length) length = reach, blocking = i;
    }
    x += length * d;
    if (blocking >= 0) {
      working.push_back(blocking);
      in_working[static_cast<size_t>(blocking)] = 1;
    }
  }
  // The result meets the constraints (and the sum) to rounding, or the start stands: on a
  // degenerate working set (rows dependent within rounding) the steps can leave them.
  const double slack = 1e-9 * scale;
  const bool meets = ((p.a * x - p.limit).array() <= slack).all() &&
                     (!p.sum_fixed || std::abs(x.sum() - start.sum()) <= slack);
  const auto f = [&](const Eigen::VectorXd& y) { return 0.5 * y.dot(p.q * y) + p.b.dot(y); };
  return meets && f(x) <= f(start) ? x : start;
}

}  // namespace ricci
