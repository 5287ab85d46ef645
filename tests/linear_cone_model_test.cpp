// The linear cone model: D of a cone set from its quadratic form over the columns' area-weighted
// sums is D of the u it forms, also after columns were dropped and their room reused; u is 0 at
// the cones and flat (K0 + H u = 0) at every other free vertex; a column costs one back-solve.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "flow/delaunay.h"
#include "flow/hessian.h"
#include "flow/linear_cone_model.h"
#include "flow/metric.h"
#include "ricci/flow/ricci_flow.h"
#include "test_meshes.h"

namespace ricci::test {
namespace {

// K0 + H u per vertex, on the input metric's intrinsic Delaunay triangulation (the model's).
Eigen::VectorXd linear_curvature(const CompactMesh& mesh, const Eigen::VectorXd& u) {
  IntrinsicTriangulation delaunay(mesh);
  ConformalStructure s = initialize_scheme(mesh, Geometry::Euclidean, SchemeOptions());
  make_input_delaunay(delaunay, s);
  const MetricState state =
      evaluate_metric(delaunay, s, Eigen::VectorXd::Zero(mesh.num_vertices()));
  std::vector<int> every(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) every[v] = v;
  HessianAssembler assembler(delaunay, every);
  return curvature(delaunay, state) + assembler.assemble(state) * u;
}

TEST(LinearConeModel, TheQuadraticFormsDistortionIsTheDistortionOfU) {
  const CompactMesh mesh = cgal_mesh("eight.off");
  LinearConeModel model(mesh, LinearSolverKind::Cholmod);
  const std::vector<std::vector<int>> sets = {{3},          {3, 40, 91}, {40, 91, 7, 150},
                                              {7, 12, 200}, {3, 12, 91}, {3, 40, 91, 7, 150, 12}};
  for (const std::vector<int>& cones : sets) {
    const LinearConeModel::Solution s = model.held(cones);
    ASSERT_TRUE(s.ok);
    const Eigen::VectorXd u = model.u(cones, s);
    EXPECT_NEAR(s.d, area_weighted_deviation(model.area(), u), 1e-10);
    EXPECT_GT(s.d, 0.01);
    const Eigen::VectorXd k = linear_curvature(mesh, u);
    double sum = 0;
    for (size_t j = 0; j < cones.size(); ++j) {
      EXPECT_EQ(u[cones[j]], 0);
      EXPECT_NEAR(k[cones[j]], s.k[j], 1e-8);
      sum += s.k[j];
    }
    EXPECT_NEAR(sum, 2 * kPi * mesh.euler_characteristic(), 1e-8);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (std::find(cones.begin(), cones.end(), v) == cones.end()) {
        EXPECT_NEAR(k[v], 0, 1e-8);
      }
    }
    model.keep_only(cones);  // the next set reuses the dropped columns' room
  }
  // Columns 3, 40, 91, 7, 150, 12 and 200, then 3 and 91 again after they were dropped, and 40,
  // 7 and 150 again for the last set (six cones: u summed four columns a pass, then the rest).
  EXPECT_EQ(model.back_solves(), 12);
}

// The vertices first, first + k, first + 2k, ...
std::vector<int> every_kth_vertex(const CompactMesh& mesh, int first, int k) {
  std::vector<int> vertices;
  for (int v = first; v < mesh.num_vertices(); v += k) vertices.push_back(v);
  return vertices;
}

// With many cones u = g + G k is one back-solve, and a column's sums with the others are read
// off another: the same D, u and curvatures as the columns give (the set above), at the same
// precision. (On a mesh this small the columns are summed up to thousands of cones: here the
// solves start at 32.)
TEST(LinearConeModel, ManyConesAreSolvedForAsFewAreSummed) {
  const CompactMesh mesh = cgal_mesh("eight.off");
  LinearConeModel model(mesh, LinearSolverKind::Cholmod, 32);
  const std::vector<int> cones = every_kth_vertex(mesh, 5, 3);
  ASSERT_GT(cones.size(), 100u);
  const LinearConeModel::Solution s = model.held(cones);
  ASSERT_TRUE(s.ok);
  const Eigen::VectorXd u = model.u(cones, s);
  // Beyond the columns, back-solves for u and for the columns' sums: the paths under test.
  EXPECT_GT(model.back_solves(), static_cast<int>(cones.size()) + 1);
  EXPECT_NEAR(s.d, area_weighted_deviation(model.area(), u), 1e-10);
  const Eigen::VectorXd k = linear_curvature(mesh, u);
  std::vector<char> is_cone(mesh.num_vertices(), 0);
  for (size_t j = 0; j < cones.size(); ++j) {
    is_cone[cones[j]] = 1;
    EXPECT_EQ(u[cones[j]], 0);
    EXPECT_NEAR(k[cones[j]], s.k[j], 1e-8);
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!is_cone[v]) {
      EXPECT_NEAR(k[v], 0, 1e-8) << v;
    }
  }
}

// A column summed with as many others as a back-solve costs passes has R(A col) solved and kept:
// the columns solved after it read their sums with it there, and D is still the D of u. Here the
// solves start at 2 columns: the first set's columns are all kept so, and the next set's new
// column costs its own back-solve and no other.
TEST(LinearConeModel, SumsWithAConeAreReadFromItsKeptSolve) {
  const CompactMesh mesh = cgal_mesh("eight.off");
  LinearConeModel model(mesh, LinearSolverKind::Cholmod, 2);
  const std::vector<int> first = {3, 40, 91, 7, 150, 12};
  ASSERT_TRUE(model.held(first).ok);
  const int solves = model.back_solves();
  EXPECT_EQ(solves, 6 + 5);  // the columns, and the sums of all but the last one paired
  std::vector<int> next = first;
  next.back() = 200;
  const LinearConeModel::Solution s = model.held(next);
  ASSERT_TRUE(s.ok);
  EXPECT_EQ(model.back_solves(), solves + 1);
  EXPECT_NEAR(s.d, area_weighted_deviation(model.area(), model.u(next, s)), 1e-10);
  // The sums of a column whose slot was reused are not read from its old solve.
  model.keep_only({3, 40});
  const std::vector<int> last = {3, 40, 300, 301};
  const LinearConeModel::Solution t = model.held(last);
  ASSERT_TRUE(t.ok);
  EXPECT_NEAR(t.d, area_weighted_deviation(model.area(), model.u(last, t)), 1e-10);
}

// Where no room is left to keep another R(A col), a column summed with many others is not
// solved again at each further sum. Room for one, solves from 3 sums: the first set's column 91
// takes the room; then cone 3 beside one new column at a time is summed by a pass with each,
// past the threshold from the third, and each set costs its new column's solve and no other (it
// used to cost one more per set from the third on), D still the D of u.
TEST(LinearConeModel, SumsPastTheKeptSolvesAreFormedByPasses) {
  const CompactMesh mesh = cgal_mesh("eight.off");
  LinearConeModel model(mesh, LinearSolverKind::Cholmod, 3, 1);
  ASSERT_TRUE(model.held({91, 40, 3}).ok);
  const int solves = model.back_solves();
  const std::vector<int> others = {7, 12, 150, 200, 300};
  for (int v : others) {
    const std::vector<int> cones = {3, v};
    const LinearConeModel::Solution s = model.held(cones);
    ASSERT_TRUE(s.ok);
    EXPECT_NEAR(s.d, area_weighted_deviation(model.area(), model.u(cones, s)), 1e-10);
    model.keep_only({91, 40, 3});
  }
  EXPECT_EQ(model.back_solves(), solves + static_cast<int>(others.size()));
}

// A column whose R(A col) was kept after passes is not solved again when a set first pairs it
// with many new columns, and keeps its one place in the room: room for two, solves from 3 sums.
// Column 3 summed with 10, 11 and 12 one at a time has its R(A col) kept; paired then with four
// new columns, it costs no solve; and after every column is dropped, two new ones both find room.
TEST(LinearConeModel, AKeptSolveIsNotSolvedAgainNorKeptTwice) {
  const CompactMesh mesh = cgal_mesh("eight.off");
  LinearConeModel model(mesh, LinearSolverKind::Cholmod, 3, 2);
  model.solve_columns({3, 10, 11, 12});
  for (int v : {10, 11, 12}) model.gram_with(v, {3});
  model.solve_columns({20, 21, 22, 23});
  int solves = model.back_solves();
  const Eigen::VectorXd row = model.gram_with(3, {20, 21, 22, 23});
  EXPECT_EQ(model.back_solves(), solves);  // read from 3's kept solve
  const LinearConeModel::Solution s = model.held({3, 20, 21, 22, 23});
  ASSERT_TRUE(s.ok);
  EXPECT_NEAR(s.d, area_weighted_deviation(model.area(), model.u({3, 20, 21, 22, 23}, s)), 1e-10);
  model.keep_only({});
  model.solve_columns({30, 34, 40, 41, 42});
  solves = model.back_solves();
  model.gram_with(30, {40, 41, 42});  // 4 sums missing: solved at once, kept
  model.gram_with(34, {40, 41, 42});  // the same, kept too: the room holds two
  EXPECT_EQ(model.back_solves(), solves + 2);
  model.solve_columns({50});
  solves = model.back_solves();
  model.gram_with(50, {30, 34});  // both read, the one sum with itself a pass
  EXPECT_EQ(model.back_solves(), solves);
  (void)row;
}

// u of several sets solved in one block (the sweeps' sets without each cone) is each set's u.
TEST(LinearConeModel, SetsSolvedTogetherGiveEachSetsU) {
  const CompactMesh mesh = cgal_mesh("eight.off");
  LinearConeModel model(mesh, LinearSolverKind::Cholmod, 16);
  const std::vector<int> cones = every_kth_vertex(mesh, 5, 7);
  ASSERT_GT(cones.size(), 20u);
  ASSERT_TRUE(model.u_by_solve(cones.size() - 1));
  std::vector<std::vector<int>> sets;
  std::vector<LinearConeModel::Solution> solutions;
  for (size_t i = 0; i < 5; ++i) {
    sets.push_back(cones);
    sets.back().erase(sets.back().begin() + static_cast<long>(i));
    solutions.push_back(model.held(sets.back()));
    ASSERT_TRUE(solutions.back().ok);
  }
  std::vector<const LinearConeModel::Solution*> pointers;
  for (const auto& s : solutions) pointers.push_back(&s);
  const int before = model.back_solves();
  const std::vector<Eigen::VectorXd> together = model.u(sets, pointers);
  EXPECT_EQ(model.back_solves(), before + 5);
  ASSERT_EQ(together.size(), 5u);
  for (size_t i = 0; i < 5; ++i) {
    const Eigen::VectorXd alone = model.u(sets[i], solutions[i]);
    EXPECT_LT((together[i] - alone).cwiseAbs().maxCoeff(), 1e-12) << "set " << i;
    for (int c : sets[i]) EXPECT_EQ(together[i][c], 0);
  }
}

TEST(LinearConeModel, AColumnBlockIsTheColumnsSolvedOneByOne) {
  const CompactMesh mesh = cgal_mesh("eight.off");
  LinearConeModel block(mesh, LinearSolverKind::Cholmod), single(mesh, LinearSolverKind::Cholmod);
  const std::vector<int> cones = {3, 40, 91, 7, 150};
  block.solve_columns(cones);
  EXPECT_EQ(block.back_solves(), 5);
  for (int c : cones) single.solve_columns({c});
  EXPECT_EQ(single.back_solves(), 5);
  const LinearConeModel::Solution a = block.held(cones), b = single.held(cones);
  ASSERT_TRUE(a.ok && b.ok);
  EXPECT_EQ(block.back_solves(), 5);  // held() found every column solved
  EXPECT_NEAR(a.d, b.d, 1e-12);
  EXPECT_LT((block.u(cones, a) - single.u(cones, b)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(LinearConeModel, ADiskWithoutConesIsTheFreeBoundaryModel) {
  const CompactMesh mesh = cgal_mesh("mannequin-devil.off");
  ASSERT_FALSE(mesh.is_closed());
  LinearConeModel model(mesh, LinearSolverKind::Cholmod);
  const LinearConeModel::Solution s = model.held({});
  ASSERT_TRUE(s.ok);
  const Eigen::VectorXd u = model.u({}, s);
  EXPECT_NEAR(s.d, area_weighted_deviation(model.area(), u), 1e-10);
  const Eigen::VectorXd k = linear_curvature(mesh, u);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.is_boundary_vertex(v)) {
      EXPECT_EQ(u[v], 0);
    } else {
      EXPECT_NEAR(k[v], 0, 1e-8);
    }
  }
}

}  // namespace
}  // namespace ricci::test
