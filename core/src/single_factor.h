// A supernodal CHOLMOD factor L (A = P^T L L^T P) with its entries rounded to single precision,
// for preconditioning: a solve with it reads half the bytes of a solve with L, and solves are
// bound by memory traffic. The arithmetic is in double precision, so the solve is one fixed
// symmetric positive definite operator, (P^T Ls Ls^T P)^-1 with Ls the rounded factor, as
// preconditioned MINRES needs. Not installed API.
#pragma once

#include <cstddef>
#include <vector>

#include <cholmod.h>
#include <Eigen/Core>

namespace ricci::detail {

class SinglePrecisionFactor {
 public:
  //! Copies a supernodal LL^T factor (CHOLMOD's int version, after a successful factorization).
  explicit SinglePrecisionFactor(const cholmod_factor& factor);

  //! (P^T Ls Ls^T P)^-1 b.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  int n_ = 0;
  std::vector<int> first_column_;         // per supernode, and one past the last
  std::vector<int> row_start_;            // per supernode: where its row indices begin in rows_
  std::vector<std::size_t> value_start_;  // per supernode: where its column-major block begins
  std::vector<int> rows_;
  std::vector<int> perm_;
  std::vector<float> values_;
};

}  // namespace ricci::detail
