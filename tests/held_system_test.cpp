// The held system of a cone set: every step (a cone added, left out, moved) gives the set's
// solution as a fresh factorization does, over hundreds of steps, refined where its drift is
// small and factored afresh where it is not.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include <Eigen/LU>

#include "flow/held_system.h"
#include "flow/linear_cone_model.h"
#include "test_meshes.h"

namespace ricci::test {
namespace {

// Every step of a held system (a cone added, left out, moved) gives the set's solution as
// LinearConeModel::held factors it afresh, on a closed surface (bordered by the constant) and on
// one with boundary, over more steps than it takes between checks of its drift.
// The held system's factorizations in `factorizations`, where given; `drift` its bound.
void expect_steps_match_held(const CompactMesh& mesh, int first, int stride, int steps,
                             int* factorizations = nullptr, double drift = HeldSystem::kDrift) {
  LinearConeModel model(mesh, LinearSolverKind::Cholmod);
  HeldSystem system(model, drift);
  const int n = mesh.num_vertices();
  const auto interior = [&](int v) {
    while (mesh.is_boundary_vertex(v % n) || (mesh.is_closed() && v % n == 0)) ++v;
    return v % n;
  };
  std::vector<int> cones;
  for (int j = 0; j < 20; ++j) {
    const int v = interior(first + j * stride);
    if (std::find(cones.begin(), cones.end(), v) == cones.end()) cones.push_back(v);
  }
  ASSERT_TRUE(system.reset(cones));
  const auto expect_same = [&](const LinearConeModel::Solution& fast, const std::vector<int>& set) {
    const LinearConeModel::Solution full = model.held(set);
    ASSERT_TRUE(full.ok && fast.ok);
    ASSERT_EQ(fast.k.size(), full.k.size());
    EXPECT_LT((fast.k - full.k).cwiseAbs().maxCoeff(), 1e-9 * (1 + full.k.cwiseAbs().maxCoeff()));
    EXPECT_NEAR(fast.c, full.c, 1e-9 * (1 + std::abs(full.c)));
    EXPECT_NEAR(fast.d, full.d, 1e-9);
  };
  int next = first + 7;
  for (int step = 0; step < steps; ++step) {
    std::vector<int> set = system.cones();
    const int i = (step * 5) % static_cast<int>(set.size());
    int v = interior(next += stride + 3);
    while (std::find(set.begin(), set.end(), v) != set.end()) v = interior(++next);
    // Solved without changing the set: one left out, one added, one moved.
    std::vector<int> without = set, added = set, moved = set;
    without.erase(without.begin() + i);
    added.push_back(v);
    moved[static_cast<size_t>(i)] = v;
    expect_same(system.without(i), without);
    expect_same(system.with(v), added);
    expect_same(system.with(v, i), moved);
    // Then the set itself changed, in turn by each kind of step.
    switch (step % 3) {
      case 0:
        system.add(v, i);
        break;
      case 1:
        system.add(v);
        break;
      default:
        system.remove(i);
        break;
    }
    ASSERT_TRUE(system.valid());
    expect_same(system.solution(), system.cones());
  }
  if (factorizations) *factorizations = system.factorizations();
}

TEST(HeldSystem, StepsGiveTheSetsSolutionAsAFreshFactorizationOnAClosedSurface) {
  expect_steps_match_held(cgal_mesh("eight.off"), 3, 17, 40);
}

TEST(HeldSystem, StepsGiveTheSetsSolutionAsAFreshFactorizationWithABoundary) {
  expect_steps_match_held(cgal_mesh("mannequin-devil.off"), 5, 23, 40);
}

// Hundreds of steps, refined at each check of the drift and not factored again where it stays
// small (as it did every 32 steps), still give the fresh factorization's solution.
TEST(HeldSystem, HundredsOfStepsKeepTheFreshFactorizationsSolution) {
  int factorizations = 0;
  expect_steps_match_held(cgal_mesh("eight.off"), 11, 29, 300, &factorizations);
  EXPECT_LT(factorizations, 300 / HeldSystem::kStepsBetweenDriftChecks);
}

// Where every check finds drift (a bound of 0), the set is factored afresh at each check (and
// where a step's pivot is too small), and the steps still give the fresh factorization's solution.
TEST(HeldSystem, DriftFoundAtEveryCheckFactorsTheSetAfresh) {
  int factorizations = 0;
  const int steps = 300, every = HeldSystem::kStepsBetweenDriftChecks + 1;
  expect_steps_match_held(cgal_mesh("eight.off"), 11, 29, steps, &factorizations, 0.0);
  EXPECT_GE(factorizations, 1 + steps / every);
}

// A system whose held inverse is a nearby system's (as rounding over many steps leaves it): one
// step of refinement brings its solution nearer the system's own, by about the two systems'
// relative distance; beyond the bound the solution is left as it was, for a fresh factorization.
TEST(HeldSystem, RefinementMovesTheHeldSolutionTowardsTheSystemsOwn) {
  const int m = 40;
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(m, m);
  a.diagonal().array() += 2.0 * m;  // diagonally dominant: well conditioned
  const Eigen::VectorXd rhs = Eigen::VectorXd::Random(m);
  const Eigen::VectorXd exact = a.partialPivLu().solve(rhs);
  const Eigen::MatrixXd nearby = a + 1e-7 * Eigen::MatrixXd::Random(m, m);
  const Eigen::MatrixXd inverse = nearby.inverse();
  const Eigen::VectorXd held = inverse * rhs;
  const double before = (held - exact).cwiseAbs().maxCoeff();
  ASSERT_GT(before, 1e-14);
  Eigen::VectorXd x = held;
  ASSERT_TRUE(refine_held_solution(a, rhs, inverse, x, 1e-6));
  EXPECT_LT((x - exact).cwiseAbs().maxCoeff(), 1e-4 * before);
  // Its residual, about 1e-9 of the scale, is beyond a bound of 1e-12: x stays.
  x = held;
  EXPECT_FALSE(refine_held_solution(a, rhs, inverse, x, 1e-12));
  EXPECT_EQ(x, held);
}

}  // namespace
}  // namespace ricci::test
