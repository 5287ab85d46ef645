// H = dK/du assembled over the mesh equals central finite differences of the curvature, is
// symmetric, and has the definiteness the theory promises (E2 semi-definite with the constants in
// its kernel on a closed surface, H2 definite).
#include "flow/hessian.h"

#include <algorithm>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "flow/metric.h"
#include "ricci/flow/scheme.h"
#include "test_meshes.h"

namespace ricci {
namespace {

const Geometry kGeometries[] = {Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical};

// The Yamabe scheme's structure on a mesh in geometry g, lengths scaled by 0.3.
ConformalStructure yamabe(const CompactMesh& mesh, Geometry g) {
  SchemeOptions options;
  options.scheme = Scheme::Yamabe;
  return initialize_scheme(mesh, g, options, 0.3);
}

std::vector<int> all_free(const CompactMesh& mesh) {
  std::vector<int> index(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) index[v] = v;
  return index;
}

// Structure with the given eps pattern, lengths of the (scaled) input, u perturbed randomly.
ConformalStructure random_structure(const CompactMesh& mesh, Geometry g,
                                    const std::vector<int>& eps, std::mt19937& rng) {
  SchemeOptions options;
  options.scheme = Scheme::Mixed;
  options.eps = eps;
  ConformalStructure s = initialize_scheme(mesh, g, options, g == Geometry::Euclidean ? 1.0 : 0.5);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  for (int v = 0; v < s.u0.size(); ++v) s.u0[v] += jitter(rng);
  return s;
}

Eigen::MatrixXd finite_difference_hessian(const CompactMesh& mesh, const ConformalStructure& s) {
  const int n = mesh.num_vertices();
  Eigen::MatrixXd h(n, n);
  const double step = 1e-6;
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd up = s.u0, um = s.u0;
    up[j] += step;
    um[j] -= step;
    const MetricState sp = evaluate_metric(mesh, s, up), sm = evaluate_metric(mesh, s, um);
    EXPECT_TRUE(sp.valid() && sm.valid());
    h.col(j) = (curvature(mesh, sp) - curvature(mesh, sm)) / (2 * step);
  }
  return h;
}

struct EpsCase {
  const char* name;
  int fixed;  // +1, 0, -1, or 2 for mixed
};

class HessianFiniteDifferences : public ::testing::TestWithParam<std::tuple<Geometry, EpsCase>> {};

TEST_P(HessianFiniteDifferences, MatchesAndIsSymmetric) {
  const auto [g, eps_case] = GetParam();
  std::mt19937 rng(42);
  for (const CompactMesh& mesh : {test::bumpy_disk(4), test::ellipsoid(1, 1.0, 0.8, 0.6)}) {
    std::vector<int> eps(mesh.num_vertices(), eps_case.fixed);
    if (eps_case.fixed == 2) {
      for (int v = 0; v < mesh.num_vertices(); ++v) eps[v] = static_cast<int>(rng() % 3) - 1;
    }
    const ConformalStructure s = random_structure(mesh, g, eps, rng);
    const MetricState state = evaluate_metric(mesh, s, s.u0);
    ASSERT_TRUE(state.valid());
    HessianAssembler assembler(mesh, all_free(mesh));
    const Eigen::MatrixXd h = Eigen::MatrixXd(assembler.assemble(state));
    const Eigen::MatrixXd fd = finite_difference_hessian(mesh, s);
    const double scale = fd.cwiseAbs().maxCoeff();
    EXPECT_LE((h - fd).cwiseAbs().maxCoeff(), 1e-6 * scale)
        << to_string(g) << " eps " << eps_case.name << " on " << mesh.num_vertices() << " vertices";
    // The finite differences themselves are symmetric: dK_i/du_j = dK_j/du_i (Lemma "Symmetry").
    EXPECT_LE((fd - fd.transpose()).cwiseAbs().maxCoeff(), 1e-6 * scale);
    EXPECT_EQ((h - h.transpose()).cwiseAbs().maxCoeff(), 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(AllGeometriesAndEps, HessianFiniteDifferences,
                         ::testing::Combine(::testing::ValuesIn(kGeometries),
                                            ::testing::Values(EpsCase{"+1", 1}, EpsCase{"0", 0},
                                                              EpsCase{"-1", -1},
                                                              EpsCase{"mixed", 2})),
                         [](const auto& test_param) {
                           const EpsCase e = std::get<1>(test_param.param);
                           const std::string eps = e.fixed == 1    ? "plus"
                                                   : e.fixed == 0  ? "zero"
                                                   : e.fixed == -1 ? "minus"
                                                                   : "mixed";
                           return to_string(std::get<0>(test_param.param)) + "_" + eps;
                         });

TEST(Hessian, ThurstonPackingMatchesFiniteDifferences) {
  const CompactMesh mesh = test::torus(12, 8);
  for (Geometry g : kGeometries) {
    SchemeOptions options;
    options.scheme = Scheme::Thurston;
    const ConformalStructure s =
        initialize_scheme(mesh, g, options, g == Geometry::Euclidean ? 1.0 : 0.3);
    const MetricState state = evaluate_metric(mesh, s, s.u0);
    ASSERT_TRUE(state.valid());
    HessianAssembler assembler(mesh, all_free(mesh));
    const Eigen::MatrixXd h = Eigen::MatrixXd(assembler.assemble(state));
    const Eigen::MatrixXd fd = finite_difference_hessian(mesh, s);
    EXPECT_LE((h - fd).cwiseAbs().maxCoeff(), 1e-6 * fd.cwiseAbs().maxCoeff()) << to_string(g);
  }
}

TEST(Hessian, EuclideanClosedSurfaceHasConstantKernelAndIsSemiDefinite) {
  const CompactMesh mesh = test::torus(10, 6);
  for (Scheme scheme : {Scheme::Tangential, Scheme::InversiveDistance, Scheme::Yamabe}) {
    SchemeOptions options;
    options.scheme = scheme;
    const ConformalStructure s = initialize_scheme(mesh, Geometry::Euclidean, options);
    HessianAssembler assembler(mesh, all_free(mesh));
    const Eigen::MatrixXd h = Eigen::MatrixXd(assembler.assemble(evaluate_metric(mesh, s, s.u0)));
    EXPECT_LE((h * Eigen::VectorXd::Ones(h.rows())).cwiseAbs().maxCoeff(), 1e-12 * h.norm());
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h).eigenvalues();
    EXPECT_GE(eig.minCoeff(), -1e-10 * eig.maxCoeff()) << to_string(scheme);
    EXPECT_GT(eig[1], 1e-8 * eig.maxCoeff()) << "kernel larger than the constants";
  }
}

TEST(Hessian, HyperbolicIsPositiveDefinite) {
  const CompactMesh mesh = test::cgal_mesh("eight.off");
  const ConformalStructure s = yamabe(mesh, Geometry::Hyperbolic);
  HessianAssembler assembler(mesh, all_free(mesh));
  const Eigen::MatrixXd h = Eigen::MatrixXd(assembler.assemble(evaluate_metric(mesh, s, s.u0)));
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h).eigenvalues().minCoeff(), 0.0);
}

TEST(Hessian, FixedVerticesAreLeftOut) {
  const CompactMesh mesh = test::bumpy_disk(4);
  const std::vector<int> index = test::interior_rows(mesh);
  const int n =
      static_cast<int>(std::count_if(index.begin(), index.end(), [](int i) { return i >= 0; }));
  SchemeOptions options;
  const ConformalStructure s = initialize_scheme(mesh, Geometry::Euclidean, options);
  const MetricState state = evaluate_metric(mesh, s, s.u0);
  HessianAssembler full(mesh, all_free(mesh)), reduced(mesh, index);
  const Eigen::MatrixXd hf = Eigen::MatrixXd(full.assemble(state));
  const Eigen::MatrixXd hr = Eigen::MatrixXd(reduced.assemble(state));
  ASSERT_EQ(hr.rows(), n);
  for (int a = 0; a < mesh.num_vertices(); ++a) {
    for (int b = 0; b < mesh.num_vertices(); ++b) {
      if (index[a] >= 0 && index[b] >= 0) {
        EXPECT_EQ(hr(index[a], index[b]), hf(a, b));
      }
    }
  }
}

// S2's H^2, formed without temporaries, is Eigen's product: at the first H and, with the pattern
// kept, at another H of the same pattern.
TEST(Hessian, SquareIsTheProductAndKeepsItsPattern) {
  const CompactMesh mesh = test::cgal_mesh("eight.off");
  const ConformalStructure s = yamabe(mesh, Geometry::Spherical);
  HessianAssembler assembler(mesh, all_free(mesh));
  SparseMatrix square;
  Eigen::VectorXd u = s.u0;
  for (int trial = 0; trial < 2; ++trial) {
    const SparseMatrix h = assembler.assemble(evaluate_metric(mesh, s, u));
    square_symmetric(h, square, trial > 0);
    const SparseMatrix expected = h * h;
    ASSERT_EQ(square.nonZeros(), expected.nonZeros());
    const double difference = (Eigen::MatrixXd(square) - Eigen::MatrixXd(expected)).norm();
    EXPECT_LT(difference, 1e-14 * Eigen::MatrixXd(expected).norm());
    u = u.array() + 0.01 * Eigen::ArrayXd::LinSpaced(u.size(), -1, 1);
  }
}

}  // namespace
}  // namespace ricci
