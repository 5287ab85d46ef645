#include "ricci/linear_solver.h"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>

#include "ricci/errors.h"

namespace ricci {

using Matrix = Eigen::SparseMatrix<double>;

struct LinearSolver::Impl {
  Eigen::CholmodSupernodalLLT<Matrix, Eigen::Lower> cholmod;
  Eigen::SimplicialLDLT<Matrix, Eigen::Lower> ldlt;
  bool analyzed = false;
};

std::string to_string(LinearSolverKind k) {
  return k == LinearSolverKind::Cholmod ? "cholmod" : "ldlt";
}

LinearSolverKind linear_solver_from_string(const std::string& name) {
  if (name == "cholmod") return LinearSolverKind::Cholmod;
  if (name == "ldlt") return LinearSolverKind::Ldlt;
  throw InvalidArgumentError("solver: unknown linear solver '" + name + "'; use cholmod or ldlt");
}

LinearSolver::LinearSolver(LinearSolverKind kind) : kind_(kind), impl_(std::make_unique<Impl>()) {
  // A failed factorization is an expected answer here (the caller shifts and retries): no warning
  // on stderr.
  impl_->cholmod.cholmod().print = 0;
}
LinearSolver::~LinearSolver() = default;

void LinearSolver::analyze(const Matrix& a) {
  if (kind_ == LinearSolverKind::Cholmod) {
    impl_->cholmod.analyzePattern(a);
  } else {
    impl_->ldlt.analyzePattern(a);
  }
  impl_->analyzed = true;
  ++num_analyses_;
}

bool LinearSolver::factorize(const Matrix& a, double shift) {
  if (!impl_->analyzed) throw SolverError("linear solver: factorize() before analyze()");
  ++num_factorizations_;
  if (kind_ == LinearSolverKind::Cholmod) {
    impl_->cholmod.setShift(shift);
    impl_->cholmod.factorize(a);
    return impl_->cholmod.info() == Eigen::Success;
  }
  impl_->ldlt.setShift(shift);
  impl_->ldlt.factorize(a);
  // LDL^T also factors indefinite matrices; positive definite means every pivot is positive.
  return impl_->ldlt.info() == Eigen::Success &&
         (impl_->ldlt.vectorD().size() == 0 || impl_->ldlt.vectorD().minCoeff() > 0);
}

Eigen::VectorXd LinearSolver::solve(const Eigen::VectorXd& b) const {
  if (kind_ == LinearSolverKind::Cholmod) return impl_->cholmod.solve(b);
  return impl_->ldlt.solve(b);
}

Eigen::MatrixXd LinearSolver::solve(const Eigen::MatrixXd& b) const {
  if (kind_ == LinearSolverKind::Cholmod) return impl_->cholmod.solve(b);
  return impl_->ldlt.solve(b);
}

}  // namespace ricci
