// The least of a convex quadratic under linear inequalities, against every choice of the
// constraints that hold with equality, tried one by one on small problems.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "flow/constrained_quadratic.h"

namespace ricci::test {
namespace {

double value(const ConstrainedQuadratic& p, const Eigen::VectorXd& x) {
  return 0.5 * x.dot(p.q * x) + p.b.dot(x);
}

bool feasible(const ConstrainedQuadratic& p, const Eigen::VectorXd& x, double sum, double slack) {
  if (p.sum_fixed && std::abs(x.sum() - sum) > slack) return false;
  return ((p.a * x - p.limit).array() <= slack).all();
}

// The minimum by enumeration: for every subset of the constraints held as equalities, the
// stationary point of f on them (and the sum's plane); the least feasible one.
double enumerated_minimum(const ConstrainedQuadratic& p, double sum) {
  const long n = p.q.rows(), rows = p.a.rows();
  double best = std::numeric_limits<double>::infinity();
  for (long subset = 0; subset < (1L << rows); ++subset) {
    std::vector<long> held;
    for (long i = 0; i < rows; ++i) {
      if (subset & (1L << i)) held.push_back(i);
    }
    const long extra = p.sum_fixed ? 1 : 0, size = n + static_cast<long>(held.size()) + extra;
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(size, size);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(size);
    kkt.topLeftCorner(n, n) = p.q;
    rhs.head(n) = -p.b;
    for (size_t j = 0; j < held.size(); ++j) {
      const long r = n + static_cast<long>(j);
      kkt.block(r, 0, 1, n) = p.a.row(held[j]);
      kkt.block(0, r, n, 1) = p.a.row(held[j]).transpose();
      rhs[r] = p.limit[held[j]];
    }
    if (p.sum_fixed) {
      kkt.block(size - 1, 0, 1, n).setOnes();
      kkt.block(0, size - 1, n, 1).setOnes();
      rhs[size - 1] = sum;
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(kkt);
    if (!lu.isInvertible()) continue;
    const Eigen::VectorXd x = lu.solve(rhs).head(n);
    if (feasible(p, x, sum, 1e-9)) best = std::min(best, value(p, x));
  }
  return best;
}

TEST(ConstrainedQuadratic, AnUpperBoundThatCutsTheMinimumHoldsIt) {
  ConstrainedQuadratic p;
  p.q = Eigen::Matrix2d::Identity();
  p.b = Eigen::Vector2d(-3, -0.5);
  p.a = Eigen::RowVector2d(1, 0);
  p.limit = Eigen::VectorXd::Constant(1, 1);
  const Eigen::VectorXd x = minimize_constrained(p, Eigen::Vector2d(0, 0));
  EXPECT_NEAR(x[0], 1, 1e-12);
  EXPECT_NEAR(x[1], 0.5, 1e-12);
  // With the sum fixed at 2 (the start's): the plane's minimum (2.25, -0.25) is cut at x0 = 1.
  p.sum_fixed = true;
  const Eigen::VectorXd y = minimize_constrained(p, Eigen::Vector2d(0.5, 1.5));
  EXPECT_NEAR(y[0], 1, 1e-12);
  EXPECT_NEAR(y[1], 1, 1e-12);
}

// A random problem of n variables and `rows` constraints that x = 0 meets: q positive definite,
// every row's limit positive, or where `degenerate`, every third row tight at 0 and every fourth
// the opposite of the one before, the two an equality in turns (rows 3, 11, ...).
ConstrainedQuadratic random_problem(std::mt19937& random, long n, long rows, bool degenerate) {
  std::normal_distribution<double> normal;
  ConstrainedQuadratic p;
  Eigen::MatrixXd m(n, n);
  for (long i = 0; i < n * n; ++i) m.data()[i] = normal(random);
  p.q = m * m.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
  p.b.resize(n);
  for (long i = 0; i < n; ++i) p.b[i] = 3 * normal(random);
  p.a.resize(rows, n);
  p.limit.resize(rows);
  for (long i = 0; i < rows; ++i) {
    for (long j = 0; j < n; ++j) p.a(i, j) = normal(random);
    p.limit[i] = degenerate && i % 3 == 0 ? 0 : std::abs(normal(random));
    if (degenerate && i % 4 == 3) {
      p.a.row(i) = -p.a.row(i - 1);
      if ((i / 4) % 2 == 0) p.limit[i - 1] = 0;  // a x = 0, met by the start
      p.limit[i] = (i / 4) % 2 == 0 ? 0 : p.limit[i - 1] + 0.1;
    }
  }
  return p;
}

// Random problems (random_problem), every other one with the sum fixed, minimized from x = 0:
// each result meets the constraints, never rises above the start and is no lower than the
// enumerated minimum. Counts those at that minimum, and those whose minimum without the
// constraints would break one (a test of the constraints, not of chance).
struct Solved {
  int trials = 0, reached = 0, cut = 0;
};
Solved solve_random_problems(unsigned seed, int trials, bool degenerate) {
  std::mt19937 random(seed);
  Solved s;
  for (int trial = 0; trial < trials; ++trial, ++s.trials) {
    const long n = (degenerate ? 1 : 2) + trial % (degenerate ? 4 : 3);
    const long rows = 2 + trial % (degenerate ? 6 : 5);
    ConstrainedQuadratic p = random_problem(random, n, rows, degenerate);
    p.sum_fixed = trial % 2 == 1;
    const Eigen::VectorXd start = Eigen::VectorXd::Zero(n);
    const Eigen::VectorXd x = minimize_constrained(p, start);
    SCOPED_TRACE(trial);
    EXPECT_TRUE(feasible(p, x, 0, 1e-9));
    EXPECT_LE(value(p, x), value(p, start) + 1e-12);
    const double expected = enumerated_minimum(p, 0);
    const double tolerance = 1e-9 * (1 + std::abs(expected));
    EXPECT_GE(value(p, x), expected - tolerance);
    s.reached += value(p, x) <= expected + tolerance;
    if (!p.sum_fixed) s.cut += !feasible(p, p.q.ldlt().solve(-p.b), 0, 0);
  }
  return s;
}

TEST(ConstrainedQuadratic, RandomProblemsReachTheEnumeratedMinimumFromAFeasibleStart) {
  const Solved s = solve_random_problems(7, 200, false);
  EXPECT_EQ(s.reached, s.trials);
  EXPECT_GT(s.cut, 50);
}

// Starts on constraints (some rows tight at x = 0), rows dependent on others, and problems of
// one variable with the sum fixed: the enumerated minimum all the same.
TEST(ConstrainedQuadratic, DegenerateProblemsKeepTheConstraintsAndNeverRise) {
  const Solved s = solve_random_problems(11, 300, true);
  EXPECT_EQ(s.reached, s.trials);  // 292 of 300 before rows the step runs along stopped blocking it
}

// A problem whose working set turns singular (an equal pair of bounds on x0 and tight bounds on
// the others): the result keeps 0 <= x0 <= 0 (it went to x0 = -0.33 without the check).
TEST(ConstrainedQuadratic, ASingularWorkingSetLeavesNoConstraintBroken) {
  ConstrainedQuadratic p;
  p.q.resize(3, 3);
  p.q << 6, 2, 0, 2, 13, 8, 0, 8, 7;
  p.b = Eigen::Vector3d(0, 3, -2);
  p.a.resize(6, 3);
  p.a << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  p.limit.resize(6);
  p.limit << 0, 0, 1, 1, 1, 1;
  const Eigen::VectorXd x = minimize_constrained(p, Eigen::Vector3d::Zero());
  EXPECT_TRUE(feasible(p, x, 0, 1e-12)) << x.transpose();
  EXPECT_NEAR(value(p, x), enumerated_minimum(p, 0), 1e-9);
}

}  // namespace
}  // namespace ricci::test
