// A supernodal CHOLMOD factor L (A = P^T L L^T P) with its entries rounded to single precision,
// for preconditioning: a solve with it reads half the bytes of a solve with L, and solves are
// bound by memory traffic. The arithmetic is in double precision, so the solve is one fixed
// symmetric positive definite operator, (P^T Ls Ls^T P)^-1 with Ls the rounded factor, as
// preconditioned MINRES needs. The independent subtrees below the elimination tree's top (a nested
// dissection's parts) are solved on two threads; the result does not depend on their timing.
// Not installed API.
#pragma once

#include <cstddef>
#include <vector>

#include <cholmod.h>
#include <Eigen/Core>

namespace ricci::detail {

class SinglePrecisionFactor {
 public:
  //! Below this many factor entries one thread solves alone (a thread costs some 0.1 ms).
  static constexpr std::size_t kTwoThreadsFrom = 2000000;

  //! Copies a supernodal LL^T factor (CHOLMOD's int version, after a successful factorization).
  explicit SinglePrecisionFactor(const cholmod_factor& factor,
                                 std::size_t two_threads_from = kTwoThreadsFrom);

  //! (P^T Ls Ls^T P)^-1 b.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

  //! Supernodes [begin, end).
  struct Range {
    int begin = 0, end = 0;
  };
  //! The subtrees each thread solves (both empty when the solve runs on one thread), and the top
  //! of the tree above them, solved by one.
  const std::vector<Range>& subtrees(int thread) const { return subtrees_[thread]; }
  Range top() const { return top_; }

 private:
  // L y = y over the supernodes [range), in order. Updates of rows at columns >= ancestors_from
  // (the top's, outside the range) are added into `ancestors` (indexed from ancestors_from)
  // instead of y.
  void forward(Range range, double* y, double* ancestors, int ancestors_from,
               std::vector<double>& local) const;
  // L^T x = x over the supernodes [range), in reverse order.
  void backward(Range range, double* x, std::vector<double>& local) const;
  void choose_subtrees(std::size_t two_threads_from);

  int n_ = 0;
  int max_rows_ = 0;                      // of a supernode
  std::vector<int> first_column_;         // per supernode, and one past the last
  std::vector<int> row_start_;            // per supernode: where its row indices begin in rows_
  std::vector<std::size_t> value_start_;  // per supernode: where its column-major block begins
  std::vector<int> rows_;
  std::vector<int> perm_;
  std::vector<float> values_;
  std::vector<Range> subtrees_[2];
  Range top_;
};

}  // namespace ricci::detail
