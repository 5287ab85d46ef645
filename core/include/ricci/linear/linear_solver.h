// Sparse symmetric positive definite solves: CHOLMOD (default) or Eigen's SimplicialLDLT.
// Symbolic analysis once per sparsity pattern, numeric factorization per call.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace ricci {

enum class LinearSolverKind { Cholmod, Ldlt };

std::string to_string(LinearSolverKind k);
//! "cholmod" or "ldlt". \throws InvalidArgumentError otherwise.
LinearSolverKind linear_solver_from_string(const std::string& name);

class LinearSolver {
 public:
  explicit LinearSolver(LinearSolverKind kind);
  ~LinearSolver();
  LinearSolver(const LinearSolver&) = delete;
  LinearSolver& operator=(const LinearSolver&) = delete;

  //! Symbolic analysis (fill-reducing ordering); call again only when the pattern changes.
  //! With `order` (CHOLMOD only: row order[k] is eliminated k-th, up to CHOLMOD's postordering,
  //! which keeps the fill), that ordering is used instead of finding one.
  void analyze(const Eigen::SparseMatrix<double>& a, const std::vector<int>* order = nullptr);
  //! Numeric factorization of a + shift I. Returns false when it is not positive definite.
  //! \pre analyze() was called with a matrix of the same pattern.
  bool factorize(const Eigen::SparseMatrix<double>& a, double shift = 0);
  //! Solves with the last successful factorization.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;
  //! solve() of each column of a sparse b: for CHOLMOD, each column's forward solve visits only
  //! the part of the factor its nonzero rows reach (a unit column's: the supernodes from its row's
  //! to the root), and the backward solves run on two threads where the factor is large.
  //! \throws SolverError without a successful factorization (CHOLMOD); InvalidArgumentError for
  //! a b of another row count.
  Eigen::MatrixXd solve_sparse(const Eigen::SparseMatrix<double>& b) const;
  //! For preconditioning: CHOLMOD's last factorization with its entries rounded to single
  //! precision, applied in double precision, so one fixed symmetric positive definite operator
  //! close to the inverse; a solve reads half the memory of solve(). solve() for the LDL^T kind.
  Eigen::VectorXd precondition(const Eigen::VectorXd& b) const;

  LinearSolverKind kind() const { return kind_; }
  //! The entries of the last analysis's factor (its fill). \pre analyze() was called, and for the
  //! LDL^T kind factorize() too.
  long factor_entries() const;
  //! The last analysis's ordering (row order[k] eliminated k-th), as analyze() takes it; empty
  //! for the LDL^T kind. \pre analyze() was called.
  std::vector<int> ordering() const;
  int num_analyses() const { return num_analyses_; }
  int num_factorizations() const { return num_factorizations_; }

 private:
  struct Impl;
  LinearSolverKind kind_;
  std::unique_ptr<Impl> impl_;
  int num_analyses_ = 0;
  int num_factorizations_ = 0;
};

}  // namespace ricci
