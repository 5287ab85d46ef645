#include "ricci/linear/linear_solver.h"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>

#include "linear/supernodal_factor.h"
#include "ricci/linear/vertex_order.h"
#include "ricci/mesh/errors.h"

namespace ricci {

using Matrix = Eigen::SparseMatrix<double>;

namespace {

// CHOLMOD's supernodal LL^T with its factor in view (for the single-precision copy), and an
// analysis in a given ordering.
class SupernodalCholmod : public Eigen::CholmodSupernodalLLT<Matrix, Eigen::Lower> {
 public:
  const cholmod_factor& factor() const { return *m_cholmodFactor; }
  // What analyzePattern() does, with CHOLMOD told the ordering.
  void analyze_in_order(const Matrix& a, const std::vector<int>& order) {
    cholmod_common& common = cholmod();
    if (m_cholmodFactor) cholmod_free_factor(&m_cholmodFactor, &common);
    cholmod_sparse view = Eigen::viewAsCholmod(a.selfadjointView<Eigen::Lower>());
    m_cholmodFactor = cholmod_analyze_p(&view, const_cast<int*>(order.data()), nullptr, 0, &common);
    m_isInitialized = true;
    m_info = Eigen::Success;
    m_analysisIsOk = true;
    m_factorizationIsOk = false;
  }
};

}  // namespace

struct LinearSolver::Impl {
  SupernodalCholmod cholmod;
  Eigen::SimplicialLDLT<Matrix, Eigen::Lower> ldlt;
  bool analyzed = false;
  bool factorized = false;
  // The last factorization in single precision, made at the first precondition() after it.
  mutable std::unique_ptr<detail::SinglePrecisionFactor> single;
  // The last factorization read in place by our own solve, made at the first solve_sparse() after
  // it.
  mutable std::unique_ptr<detail::SupernodalFactor<double>> exact;
  int default_first_ordering = 0;  // CHOLMOD's first method when it chooses the ordering itself
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
  impl_->default_first_ordering = impl_->cholmod.cholmod().method[0].ordering;
}
LinearSolver::~LinearSolver() = default;

void LinearSolver::analyze(const Matrix& a, const std::vector<int>* order) {
  if (kind_ == LinearSolverKind::Cholmod) {
    // CHOLMOD's default tries AMD first and METIS where AMD's fill is poor, as it always is on a
    // surface mesh this large; AMD's attempt then costs a fifth of METIS's time for nothing.
    cholmod_common& common = impl_->cholmod.cholmod();
    const bool large = a.rows() >= kNestedDissectionRows;
    common.nmethods = order || large ? 1 : 0;
    common.method[0].ordering = order   ? CHOLMOD_GIVEN
                                : large ? CHOLMOD_METIS
                                        : impl_->default_first_ordering;
    if (order) {
      if (static_cast<long>(order->size()) != a.rows())
        throw SolverError("linear solver: an ordering of another size than the matrix");
      impl_->cholmod.analyze_in_order(a, *order);
    } else {
      const std::lock_guard<std::mutex> lock(detail::nested_dissection_mutex());
      impl_->cholmod.analyzePattern(a);
    }
    impl_->factorized = false;
    impl_->single.reset();
    impl_->exact.reset();
  } else {
    impl_->ldlt.analyzePattern(a);
  }
  impl_->analyzed = true;
  ++num_analyses_;
}

bool LinearSolver::factorize(const Matrix& a, double shift) {
  if (!impl_->analyzed) throw SolverError("linear solver: factorize() before analyze()");
  ++num_factorizations_;
  impl_->single.reset();
  impl_->exact.reset();
  if (kind_ == LinearSolverKind::Cholmod) {
    impl_->cholmod.setShift(shift);
    impl_->cholmod.factorize(a);
    impl_->factorized = impl_->cholmod.info() == Eigen::Success;
    return impl_->factorized;
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

Eigen::VectorXd LinearSolver::precondition(const Eigen::VectorXd& b) const {
  if (kind_ != LinearSolverKind::Cholmod || !impl_->factorized) return solve(b);
  if (!impl_->single) {
    impl_->single = std::make_unique<detail::SinglePrecisionFactor>(impl_->cholmod.factor());
  }
  return impl_->single->solve(b);
}

Eigen::MatrixXd LinearSolver::solve_sparse(const Eigen::SparseMatrix<double>& b) const {
  const bool cholmod = kind_ == LinearSolverKind::Cholmod;
  if (cholmod && !impl_->factorized) {
    throw SolverError("linear solver: solve_sparse() without a successful factorization");
  }
  const long rows = cholmod ? static_cast<long>(impl_->cholmod.factor().n) : impl_->ldlt.rows();
  if (b.rows() != rows) {
    throw InvalidArgumentError("linear solver: a right-hand side of another size than the matrix");
  }
  if (!cholmod) return impl_->ldlt.solve(Eigen::MatrixXd(b));
  if (!impl_->exact) {
    impl_->exact = std::make_unique<detail::SupernodalFactor<double>>(impl_->cholmod.factor());
  }
  return impl_->exact->solve_sparse(b);
}

long LinearSolver::factor_entries() const {
  if (kind_ == LinearSolverKind::Cholmod) {
    const cholmod_factor& l = impl_->cholmod.factor();
    // Supernodal: the dense blocks' entries; simplicial: the column counts.
    if (l.is_super) return static_cast<long>(l.xsize);
    long entries = 0;
    for (size_t j = 0; j < l.n; ++j) entries += static_cast<const int*>(l.ColCount)[j];
    return entries;
  }
  return impl_->ldlt.matrixL().nestedExpression().nonZeros() + impl_->ldlt.rows();
}

std::vector<int> LinearSolver::ordering() const {
  if (kind_ != LinearSolverKind::Cholmod) return {};
  const cholmod_factor& l = impl_->cholmod.factor();
  const int* perm = static_cast<const int*>(l.Perm);
  return perm ? std::vector<int>(perm, perm + l.n) : std::vector<int>{};
}

Eigen::MatrixXd LinearSolver::solve(const Eigen::MatrixXd& b) const {
  if (kind_ == LinearSolverKind::Cholmod) return impl_->cholmod.solve(b);
  return impl_->ldlt.solve(b);
}

}  // namespace ricci
