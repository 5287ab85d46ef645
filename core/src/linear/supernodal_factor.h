// CHOLMOD's supernodal LL^T factor (A = P^T L L^T P) solved by our own loops, in two forms: with
// its entries rounded to single precision, for preconditioning (a solve reads half the bytes of a
// solve with L, and solves are bound by memory traffic; the arithmetic is in double precision, so
// the solve is one fixed symmetric positive definite operator, (P^T Ls Ls^T P)^-1 with Ls the
// rounded factor, as preconditioned MINRES needs), and in double precision reading CHOLMOD's
// entries where they are, for sparse right-hand sides (the cone placement's columns A^-1 e_v): the
// forward solve of a right-hand side visits only the supernodes from its nonzero rows' up to the
// root, a fraction of the factor. The independent subtrees below the elimination tree's top (a
// nested dissection's parts) are solved on two threads; the result does not depend on their
// timing. Not installed API.
#pragma once

#include <cstddef>
#include <vector>

#include <cholmod.h>
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace ricci::detail {

template <class Value>
class SupernodalFactor {
 public:
  //! Below this many factor entries one thread solves alone (a thread costs some 0.1 ms).
  static constexpr std::size_t kTwoThreadsFrom = 2000000;

  //! A supernodal LL^T factor (CHOLMOD's int version, after a successful factorization): copied
  //! and rounded for float; for double its entries are read in place, so the factor must outlive
  //! this and stay unchanged.
  explicit SupernodalFactor(const cholmod_factor& factor,
                            std::size_t two_threads_from = kTwoThreadsFrom);
  // Not copied: the entries are read through a pointer (into own_ for float).
  SupernodalFactor(const SupernodalFactor&) = delete;
  SupernodalFactor& operator=(const SupernodalFactor&) = delete;

  //! (P^T L L^T P)^-1 b.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  //! (P^T L L^T P)^-1 b for each column of b, the forward solves over the supernodes its nonzero
  //! rows reach.
  Eigen::MatrixXd solve_sparse(const Eigen::SparseMatrix<double>& b) const;

  //! Supernodes [begin, end).
  struct Range {
    int begin = 0, end = 0;
  };
  //! The subtrees each thread solves (both empty when the solve runs on one thread), and the top
  //! of the tree above them, solved by one.
  const std::vector<Range>& subtrees(int thread) const { return subtrees_[thread]; }
  Range top() const { return top_; }
  //! Factor entries the forward solve of e_row reads (its supernodes' blocks).
  std::size_t entries_reached(int row) const;

 private:
  // L y = y at supernode q. Updates of rows at columns >= ancestors_from (the top's, outside the
  // subtree being solved) are added into `ancestors` (indexed from ancestors_from) instead of y.
  void forward(int q, double* y, double* ancestors, int ancestors_from,
               std::vector<double>& local) const;
  void forward(Range range, double* y, double* ancestors, int ancestors_from,
               std::vector<double>& local) const;
  // L^T x = x over the supernodes [range), in reverse order, for `count` columns of x (each n_
  // long, side by side).
  void backward(Range range, double* x, int count, std::vector<double>& local) const;
  // Backward over the whole tree, the subtrees on two threads where there are.
  void backward(double* x, int count) const;
  void choose_subtrees(std::size_t two_threads_from);

  int n_ = 0;
  int max_rows_ = 0;                      // of a supernode
  std::vector<int> first_column_;         // per supernode, and one past the last
  std::vector<int> row_start_;            // per supernode: where its row indices begin in rows_
  std::vector<std::size_t> value_start_;  // per supernode: where its column-major block begins
  std::vector<int> rows_;
  std::vector<int> perm_, inverse_perm_;
  std::vector<int> parent_;        // per supernode, -1 at a root
  std::vector<int> supernode_of_;  // per column
  std::vector<Value> own_;         // float's rounded entries
  const Value* values_ = nullptr;
  std::vector<Range> subtrees_[2];
  Range top_;
};

extern template class SupernodalFactor<float>;
extern template class SupernodalFactor<double>;
using SinglePrecisionFactor = SupernodalFactor<float>;

}  // namespace ricci::detail
