// The linear solver's preconditioning solve: CHOLMOD's factor rounded to single precision, applied
// in double precision. It must stay close to the exact solve, differ from it by the rounding (so
// the copy is what runs), and be one symmetric positive definite operator, as MINRES needs. And
// its solve of sparse right-hand sides with the double-precision factor: CHOLMOD's solve to
// rounding, on one thread and on two.
#include "ricci/linear/linear_solver.h"

#include <algorithm>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include <dlfcn.h>

#include "flow/hessian.h"
#include "flow/metric.h"
#include "linear/blas_threads.h"
#include "linear/minres.h"
#include "linear/supernodal_factor.h"
#include "mesh/two_threads.h"
#include "no_new_threads.h"
#include "ricci/flow/scheme.h"
#include "ricci/linear/vertex_order.h"
#include "ricci/mesh/errors.h"
#include "test_meshes.h"

namespace ricci {
namespace {

// The E2 Yamabe Hessian of lion-head.off (a disk scan) with its boundary held: positive definite.
Eigen::SparseMatrix<double> lion_head_hessian() {
  const CompactMesh mesh = test::cgal_mesh("lion-head.off");
  const std::vector<int> index = test::interior_rows(mesh);
  const ConformalStructure s = initialize_scheme(mesh, Geometry::Euclidean, SchemeOptions());
  HessianAssembler assembler(mesh, index);
  return assembler.assemble(evaluate_metric(mesh, s, s.u0));
}

// lion_head_hessian() analysed and factorized by a solver of the given kind.
struct Factored {
  explicit Factored(LinearSolverKind kind) : solver(kind) {
    solver.analyze(h);
    factorized = solver.factorize(h);
  }
  const Eigen::SparseMatrix<double> h = lion_head_hessian();
  LinearSolver solver;
  bool factorized = false;
};

Eigen::VectorXd random_vector(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> d(-1, 1);
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) x[i] = d(rng);
  return x;
}

TEST(LinearSolver, PreconditioningSolveIsTheFactorInSinglePrecision) {
  Factored f(LinearSolverKind::Cholmod);
  ASSERT_TRUE(f.factorized);
  const Eigen::SparseMatrix<double>& h = f.h;
  LinearSolver& solver = f.solver;
  std::mt19937 rng(7);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd b = random_vector(static_cast<int>(h.rows()), rng);
    const Eigen::VectorXd exact = solver.solve(b), rounded = solver.precondition(b);
    const double difference = (rounded - exact).norm() / exact.norm();
    EXPECT_LT(difference, 1e-4);   // float's rounding, amplified by H's condition
    EXPECT_GT(difference, 1e-12);  // not the double-precision factor
    EXPECT_LT((h * rounded - b).norm() / b.norm(), 1e-3);
  }
}

TEST(LinearSolver, PreconditioningSolveIsSymmetricAndPositive) {
  Factored f(LinearSolverKind::Cholmod);
  ASSERT_TRUE(f.factorized);
  const Eigen::SparseMatrix<double>& h = f.h;
  LinearSolver& solver = f.solver;
  std::mt19937 rng(11);
  const int n = static_cast<int>(h.rows());
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd x = random_vector(n, rng), y = random_vector(n, rng);
    const Eigen::VectorXd px = solver.precondition(x), py = solver.precondition(y);
    EXPECT_NEAR(y.dot(px), x.dot(py), 1e-12 * px.norm() * y.norm());
    EXPECT_GT(x.dot(px), 0.0);
  }
}

TEST(LinearSolver, MinresPreconditionedInSinglePrecisionReachesDoublePrecision) {
  Factored f(LinearSolverKind::Cholmod);
  ASSERT_TRUE(f.factorized);
  const Eigen::SparseMatrix<double>& h = f.h;
  LinearSolver& solver = f.solver;
  std::mt19937 rng(3);
  const Eigen::VectorXd b = random_vector(static_cast<int>(h.rows()), rng);
  const detail::MinresResult m = detail::minres(
      [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return h * x; },
      [&](const Eigen::VectorXd& x) { return solver.precondition(x); }, b, 1e-13, 20);
  EXPECT_LE(m.relative_residual, 1e-13);
  EXPECT_LE(m.iterations, 6);
  EXPECT_LT((h * m.x - b).norm() / b.norm(), 1e-11);
}

TEST(LinearSolver, LdltPreconditionsWithItsExactSolve) {
  Factored f(LinearSolverKind::Ldlt);
  ASSERT_TRUE(f.factorized);
  const Eigen::SparseMatrix<double>& h = f.h;
  LinearSolver& solver = f.solver;
  std::mt19937 rng(5);
  const Eigen::VectorXd b = random_vector(static_cast<int>(h.rows()), rng);
  EXPECT_EQ((solver.precondition(b) - solver.solve(b)).norm(), 0.0);
}

// CHOLMOD's supernodal factor of a, ordered by METIS (a nested dissection: a tree with a top).
class MetisFactor {
 public:
  explicit MetisFactor(const Eigen::SparseMatrix<double>& a) {
    cholmod_start(&common_);
    common_.supernodal = CHOLMOD_SUPERNODAL;
    common_.nmethods = 1;
    common_.method[0].ordering = CHOLMOD_METIS;
    Eigen::SparseMatrix<double> lower = a.triangularView<Eigen::Lower>();
    lower.makeCompressed();
    cholmod_sparse view{};
    view.nrow = view.ncol = static_cast<size_t>(lower.rows());
    view.nzmax = static_cast<size_t>(lower.nonZeros());
    view.p = lower.outerIndexPtr();
    view.i = lower.innerIndexPtr();
    view.x = lower.valuePtr();
    view.stype = -1;
    view.itype = CHOLMOD_INT;
    view.xtype = CHOLMOD_REAL;
    view.dtype = CHOLMOD_DOUBLE;
    view.sorted = 1;
    view.packed = 1;
    factor_ = cholmod_analyze(&view, &common_);
    cholmod_factorize(&view, factor_, &common_);
  }
  ~MetisFactor() {
    cholmod_free_factor(&factor_, &common_);
    cholmod_finish(&common_);
  }
  const cholmod_factor& factor() const { return *factor_; }

 private:
  cholmod_common common_;
  cholmod_factor* factor_ = nullptr;
};

TEST(LinearSolver, TwoThreadsSolveWhatOneSolves) {
  const Eigen::SparseMatrix<double> h = lion_head_hessian();
  const MetisFactor cholmod(h);
  ASSERT_EQ(cholmod.factor().minor, cholmod.factor().n);
  const detail::SinglePrecisionFactor one(cholmod.factor()), two(cholmod.factor(), 0);
  ASSERT_TRUE(one.subtrees(0).empty());  // lion-head.off is below the two-thread size
  ASSERT_FALSE(two.subtrees(0).empty());
  ASSERT_FALSE(two.subtrees(1).empty());
  std::mt19937 rng(13);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd b = random_vector(static_cast<int>(h.rows()), rng);
    const Eigen::VectorXd x1 = one.solve(b), x2 = two.solve(b);
    EXPECT_LT((x2 - x1).norm(), 1e-12 * x1.norm());  // the top's sums in another order
    for (int again = 0; again < 3; ++again) {
      EXPECT_EQ((two.solve(b) - x2).norm(), 0.0);  // whatever the threads' timing
    }
  }
}

// Where no thread can be made, this one does the work of both: the loops' halves, the two tasks,
// the factor's two subtrees, with the results of two threads.
TEST(LinearSolver, WhereNoThreadCanBeMadeOneThreadSolvesWhatTwoSolve) {
  const Eigen::SparseMatrix<double> h = lion_head_hessian();
  const MetisFactor cholmod(h);
  ASSERT_EQ(cholmod.factor().minor, cholmod.factor().n);
  const detail::SinglePrecisionFactor two(cholmod.factor(), 0);
  ASSERT_FALSE(two.subtrees(0).empty());
  std::mt19937 rng(17);
  const Eigen::VectorXd b = random_vector(static_cast<int>(h.rows()), rng);
  const Eigen::VectorXd on_two = two.solve(b);
  const std::thread::id here = std::this_thread::get_id();
  const test::NoNewThreads no_threads;
  ASSERT_TRUE(no_threads.held());
  ASSERT_THROW(std::thread([] {}).join(), std::system_error) << "the scope did not hold threads";
  EXPECT_EQ((two.solve(b) - on_two).norm(), 0.0);
  std::vector<int> part_of(1000, -1);
  std::vector<std::thread::id> ran_on(2);
  detail::in_two_halves(
      1000,
      [&](int part, int begin, int end) {
        ran_on[part] = std::this_thread::get_id();
        for (int i = begin; i < end; ++i) part_of[i] = part;
      },
      0);
  EXPECT_EQ(ran_on[0], here);
  EXPECT_EQ(ran_on[1], here);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(part_of[i], i < 500 ? 0 : 1) << i;
  int first = 0, second = 0;
  detail::both([&] { first = 1; }, [&] { second = first + 1; }, true);
  EXPECT_EQ(second, 2);  // one after the other
  // An exception of the first half is thrown once the second has run, as with two threads.
  bool second_ran = false;
  EXPECT_THROW(
      detail::both([] { throw std::runtime_error("first"); }, [&] { second_ran = true; }, true),
      std::runtime_error);
  EXPECT_TRUE(second_ran);
}

// Unit columns and a column of several nonzeros, as the cone placement solves them: each
// column's forward solve over the supernodes its rows reach, then one backward solve for all.
Eigen::SparseMatrix<double> sparse_columns(int n) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int j = 0; j < 5; ++j) entries.emplace_back((j * 7919) % n, j, 1.0);
  for (int row : {3, n / 2, n - 1}) entries.emplace_back(row, 5, 0.5 + row % 3);
  Eigen::SparseMatrix<double> b(n, 6);
  b.setFromTriplets(entries.begin(), entries.end());
  return b;
}

TEST(LinearSolver, SparseRightHandSidesSolveAsCholmodSolvesThem) {
  Factored f(LinearSolverKind::Cholmod);
  ASSERT_TRUE(f.factorized);
  const Eigen::SparseMatrix<double> b = sparse_columns(static_cast<int>(f.h.rows()));
  const Eigen::MatrixXd exact = f.solver.solve(Eigen::MatrixXd(b));
  const Eigen::MatrixXd sparse = f.solver.solve_sparse(b);
  ASSERT_EQ(sparse.cols(), b.cols());
  for (long j = 0; j < b.cols(); ++j) {
    EXPECT_LT((sparse.col(j) - exact.col(j)).norm(), 1e-12 * exact.col(j).norm()) << j;
    EXPECT_LT((f.h * sparse.col(j) - b.col(j)).norm(), 1e-10) << j;
  }
  // The LDL^T kind solves them densely.
  Factored ldlt(LinearSolverKind::Ldlt);
  ASSERT_TRUE(ldlt.factorized);
  EXPECT_LT((ldlt.solver.solve_sparse(b) - exact).norm(), 1e-10 * exact.norm());
  // Another size, or no factorization: refused.
  const Eigen::SparseMatrix<double> wrong(b.rows() + 1, 1);
  EXPECT_THROW(f.solver.solve_sparse(wrong), InvalidArgumentError);
  EXPECT_THROW(ldlt.solver.solve_sparse(wrong), InvalidArgumentError);
  LinearSolver unfactored(LinearSolverKind::Cholmod);
  unfactored.analyze(f.h);
  EXPECT_THROW(unfactored.solve_sparse(b), SolverError);
  // After another factorization (a shift) the solves are the new factor's.
  ASSERT_TRUE(f.solver.factorize(f.h, 1.0));
  const Eigen::MatrixXd shifted = f.solver.solve_sparse(b);
  const Eigen::SparseMatrix<double> identity = [&] {
    Eigen::SparseMatrix<double> i(f.h.rows(), f.h.cols());
    i.setIdentity();
    return i;
  }();
  for (long j = 0; j < b.cols(); ++j) {
    EXPECT_LT(((f.h + identity) * shifted.col(j) - b.col(j)).norm(), 1e-10) << j;
  }
}

TEST(LinearSolver, SparseSolvesReachAFractionOfTheFactorAndRunOnTwoThreads) {
  const Eigen::SparseMatrix<double> h = lion_head_hessian();
  const MetisFactor cholmod(h);
  ASSERT_EQ(cholmod.factor().minor, cholmod.factor().n);
  const detail::SupernodalFactor<double> one(cholmod.factor()), two(cholmod.factor(), 0);
  ASSERT_TRUE(one.subtrees(0).empty());
  ASSERT_FALSE(two.subtrees(0).empty());
  const int n = static_cast<int>(h.rows());
  // A unit column's forward solve reads its supernodes' path to the root: on a nested
  // dissection's tree, far less than the whole factor.
  std::size_t most = 0;
  for (int row = 0; row < n; row += 97) most = std::max(most, one.entries_reached(row));
  EXPECT_LT(static_cast<double>(most), 0.25 * static_cast<double>(cholmod.factor().xsize));
  const Eigen::SparseMatrix<double> b = sparse_columns(n);
  const Eigen::MatrixXd x1 = one.solve_sparse(b), x2 = two.solve_sparse(b);
  for (long j = 0; j < b.cols(); ++j) {
    EXPECT_LT((h * x1.col(j) - b.col(j)).norm(), 1e-10) << j;
    // The forward solves run on one thread, and the subtrees' backward solves share nothing.
    EXPECT_EQ((x2.col(j) - x1.col(j)).norm(), 0.0) << j;
  }
  EXPECT_EQ((two.solve_sparse(b) - x2).norm(), 0.0);  // whatever the threads' timing
  // The dense solve of the double factor: CHOLMOD's.
  std::mt19937 rng(17);
  const Eigen::VectorXd r = random_vector(n, rng);
  EXPECT_LT((h * two.solve(r) - r).norm(), 1e-10 * r.norm());
}

// The ordering an analysis found, given back, is analysed to the same fill, and another
// ordering to another: the flow reuses the last one after flips (StepSolver).
TEST(LinearSolver, AnAnalysisGivesItsOrderingBack) {
  Factored own(LinearSolverKind::Cholmod);
  ASSERT_TRUE(own.factorized);
  const std::vector<int> order = own.solver.ordering();
  const int n = static_cast<int>(own.h.rows());
  ASSERT_EQ(static_cast<int>(order.size()), n);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < n; ++i) ASSERT_EQ(sorted[i], i);  // a permutation
  std::vector<int> identity(static_cast<size_t>(n));
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_NE(order, identity);

  LinearSolver again(LinearSolverKind::Cholmod);
  again.analyze(own.h, &order);
  EXPECT_EQ(again.factor_entries(), own.solver.factor_entries());
  EXPECT_EQ(again.ordering(), order);
  LinearSolver in_rows(LinearSolverKind::Cholmod);
  in_rows.analyze(own.h, &identity);
  EXPECT_GT(in_rows.factor_entries(), 2 * own.solver.factor_entries());
  EXPECT_TRUE(LinearSolver(LinearSolverKind::Ldlt).ordering().empty());
}

// A fill-reducing order found ahead from the mesh's vertex graph, restricted to the rows of a
// Hessian that holds the boundary, fills at most a quarter more than the Hessian's own (CHOLMOD's
// choice, AMD at this size) and solves the same.
TEST(VertexOrder, OrderOfTheVertexGraphServesAHessianOfItsInterior) {
  const CompactMesh mesh = test::cgal_mesh("lion-head.off");
  const VertexOrder order = VertexOrder::start(mesh.num_vertices(), mesh.faces(), 0);
  ASSERT_FALSE(order.empty());
  ASSERT_EQ(order.num_vertices(), mesh.num_vertices());
  const std::vector<int> rank = order.ranks();
  std::vector<int> sorted = rank;
  std::sort(sorted.begin(), sorted.end());
  for (int v = 0; v < mesh.num_vertices(); ++v) ASSERT_EQ(sorted[v], v);  // a permutation

  // The interior's rows in the order: each once, by rank.
  const std::vector<int> index = test::interior_rows(mesh);
  const std::vector<int> rows = order.rows(index);
  const int interior =
      static_cast<int>(std::count_if(index.begin(), index.end(), [](int row) { return row >= 0; }));
  ASSERT_EQ(static_cast<int>(rows.size()), interior);
  std::vector<int> vertex_of_row(static_cast<size_t>(interior), -1);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (index[v] >= 0) vertex_of_row[index[v]] = v;
  std::vector<int> seen(static_cast<size_t>(interior), 0);
  for (size_t i = 0; i < rows.size(); ++i) {
    ASSERT_GE(rows[i], 0);
    ASSERT_LT(rows[i], interior);
    EXPECT_EQ(++seen[rows[i]], 1);
    if (i > 0) {
      EXPECT_LT(rank[vertex_of_row[rows[i - 1]]], rank[vertex_of_row[rows[i]]]);
    }
  }
  EXPECT_TRUE(order.rows(std::vector<int>(index.begin(), index.end() - 1)).empty());

  Factored own(LinearSolverKind::Cholmod);
  ASSERT_TRUE(own.factorized);
  LinearSolver ahead(LinearSolverKind::Cholmod);
  ahead.analyze(own.h, &rows);
  EXPECT_LE(ahead.factor_entries(), 1.25 * static_cast<double>(own.solver.factor_entries()));
  ASSERT_TRUE(ahead.factorize(own.h));
  std::mt19937 rng(3);
  const Eigen::VectorXd b = random_vector(static_cast<int>(own.h.rows()), rng);
  const Eigen::VectorXd x = own.solver.solve(b);
  EXPECT_LT((ahead.solve(b) - x).norm() / x.norm(), 1e-10);

  std::vector<int> wrong_size(rows.begin(), rows.end() - 1);
  EXPECT_THROW(ahead.analyze(own.h, &wrong_size), SolverError);
}

// The order of a part of the mesh (a component of a repaired mesh) follows its vertex map; a map
// outside the mesh, or a mesh below the size threshold, gets none.
TEST(VertexOrder, RestrictedOrderFollowsTheVertexMap) {
  const CompactMesh mesh = test::cgal_mesh("lion-head.off");
  const VertexOrder order = VertexOrder::start(mesh.num_vertices(), mesh.faces(), 0);
  const std::vector<int> rank = order.ranks();
  const std::vector<int> from = {5, 3, 3, 0};
  const VertexOrder part = order.restricted(from);
  ASSERT_EQ(part.num_vertices(), 4);
  EXPECT_EQ(part.ranks(), (std::vector<int>{rank[5], rank[3], rank[3], rank[0]}));
  const VertexOrder deeper = part.restricted({3, 0});
  EXPECT_EQ(deeper.ranks(), (std::vector<int>{rank[0], rank[5]}));
  // Copies of a vertex share its rank and are listed by vertex index, next to each other;
  // vertices without a row are left out.
  const std::vector<int> rows = part.rows({0, 1, 2, 3});
  ASSERT_EQ(rows.size(), 4u);
  const auto at = [&](int row) { return std::find(rows.begin(), rows.end(), row) - rows.begin(); };
  EXPECT_EQ(at(2), at(1) + 1);
  EXPECT_EQ(part.rows({-1, 0, 1, -1}), (std::vector<int>{0, 1}));

  EXPECT_TRUE(order.restricted({0, mesh.num_vertices()}).empty());
  EXPECT_TRUE(VertexOrder::start(mesh.num_vertices(), mesh.faces()).empty());
  EXPECT_TRUE(VertexOrder().restricted({0}).empty());
  EXPECT_TRUE(VertexOrder().rows({}).empty());
}

}  // namespace
}  // namespace ricci

// While a SingleThreadedBlas lives, the OpenBLAS that CHOLMOD calls (scripts/setup.sh installs
// it) runs on one thread; its count comes back when the last one alive ends, in whatever order
// they end (guards of two threads share the process's count).
TEST(SingleThreadedBlas, HoldsOpenBlasToOneThreadAndRestoresIt) {
  const auto get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  const auto set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (get == nullptr || set == nullptr) GTEST_SKIP() << "the BLAS linked is not OpenBLAS";
  const int before = get();
  struct Restore {
    void (*set)(int);
    int count;
    ~Restore() { set(count); }
  } restore{set, before};
  set(2);  // as on two cores, whatever OPENBLAS_NUM_THREADS said
  if (get() != 2) GTEST_SKIP() << "this OpenBLAS runs on one thread at most";
  {
    const ricci::detail::SingleThreadedBlas one;
    EXPECT_EQ(get(), 1);
    {
      const ricci::detail::SingleThreadedBlas inside;
      EXPECT_EQ(get(), 1);
    }
    EXPECT_EQ(get(), 1);
  }
  EXPECT_EQ(get(), 2);
  std::optional<ricci::detail::SingleThreadedBlas> first, second;
  first.emplace();
  second.emplace();
  first.reset();  // the first made ends first: the second still holds the count
  EXPECT_EQ(get(), 1);
  second.reset();
  EXPECT_EQ(get(), 2);
}
