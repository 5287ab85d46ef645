// Preconditioned MINRES (Paige and Saunders 1975) for symmetric, possibly indefinite or singular
// systems A x = b with a symmetric positive definite preconditioner M: the iterate minimizes
// |b - A x| in the M^-1 norm over the Krylov space of M^-1 A. Short recurrences: a handful of
// vectors whatever the iteration count. Not installed API.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace ricci::detail {

struct MinresResult {
  Eigen::VectorXd x;
  int iterations = 0;
  //! |b - A x| / |b| in the M^-1 norm, as the recurrence estimates it.
  double relative_residual = 1;
};

//! Iterates until the estimated relative residual is at most rtol, or max_iterations.
//! `apply(v)` returns A v, `precondition(r)` returns M^-1 r.
template <class Apply, class Precondition>
MinresResult minres(const Apply& apply, const Precondition& precondition, const Eigen::VectorXd& b,
                    double rtol, int max_iterations) {
  MinresResult out;
  const long n = b.size();
  out.x = Eigen::VectorXd::Zero(n);
  // The Lanczos vectors of M^-1 A in the M inner product: r_prev, r_cur hold M times them.
  Eigen::VectorXd r_prev = b, r_cur = b;
  Eigen::VectorXd y = precondition(r_cur);
  const double beta1 = std::sqrt(std::max(0.0, r_cur.dot(y)));
  if (!(beta1 > 0)) {
    out.relative_residual = 0;
    return out;
  }
  double beta = beta1, beta_old = 0;
  // The QR factorization of the tridiagonal Lanczos matrix by Givens rotations (c, s), with the
  // entries it carries from one column to the next.
  double c = -1, s = 0, delta_bar = 0, epsilon = 0, phi_bar = beta1;
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n), w_prev = Eigen::VectorXd::Zero(n);
  for (int k = 1; k <= max_iterations; ++k) {
    const Eigen::VectorXd v = y / beta;
    y = apply(v);
    if (k >= 2) y -= (beta / beta_old) * r_prev;
    const double alpha = v.dot(y);
    y -= (alpha / beta) * r_cur;
    r_prev.swap(r_cur);
    r_cur = y;
    y = precondition(r_cur);
    beta_old = beta;
    beta = std::sqrt(std::max(0.0, r_cur.dot(y)));
    // Apply the previous rotation to the new column, then the new rotation.
    const double epsilon_old = epsilon;
    const double delta = c * delta_bar + s * alpha;
    const double gamma_bar = s * delta_bar - c * alpha;
    epsilon = s * beta;
    delta_bar = -c * beta;
    // sqrt rather than std::hypot: glibc 2.35's new hypot symbol would keep the wheel from its
    // manylinux tag (auditwheel), and these entries are far from overflow.
    const double gamma = std::max(std::sqrt(gamma_bar * gamma_bar + beta * beta),
                                  std::numeric_limits<double>::min());
    c = gamma_bar / gamma;
    s = beta / gamma;
    const double phi = c * phi_bar;
    phi_bar *= s;
    // The search directions: w_k = (v_k - epsilon_old w_{k-2} - delta w_{k-1}) / gamma.
    Eigen::VectorXd w_next = (v - epsilon_old * w_prev - delta * w) / gamma;
    w_prev.swap(w);
    w.swap(w_next);
    out.x += phi * w;
    out.iterations = k;
    out.relative_residual = phi_bar / beta1;
    if (out.relative_residual <= rtol || !(beta > 0)) break;
  }
  return out;
}

}  // namespace ricci::detail
