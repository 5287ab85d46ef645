// The flow itself: convergence of every geometry and scheme on smooth meshes of a topology that
// admits them, quadratic convergence (few Newton iterations), Gauss-Bonnet, and the invariants
// of each scheme checked independently of the solver.
#include "ricci/flow/ricci_flow.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <gtest/gtest.h>

#include "flow/flow_steps.h"
#include "flow/metric.h"
#include "ricci/flow/presets.h"
#include "ricci/mesh/errors.h"
#include "ricci/pipeline/uniformize.h"
#include "test_meshes.h"

namespace ricci {
namespace {

const Scheme kSchemes[] = {Scheme::Tangential, Scheme::Thurston,      Scheme::InversiveDistance,
                           Scheme::Yamabe,     Scheme::VirtualRadius, Scheme::Mixed};

void expect_gauss_bonnet(const CompactMesh& mesh, Geometry g, const FlowResult& r) {
  const double lhs = r.curvature.sum() + background_curvature(g) * r.area;
  EXPECT_NEAR(lhs, 2 * kPi * mesh.euler_characteristic(), 1e-9);
}

// One Newton run on mesh, recorded as a test property; asserts convergence in few iterations.
FlowResult expect_converges(const std::string& mesh_name, const CompactMesh& mesh, Geometry g,
                            Scheme scheme, const TargetCurvature& target, int max_iterations) {
  FlowOptions options;
  options.tolerance = 1e-10;
  const FlowResult r =
      compute_ricci_flow(mesh, g, test::scheme_options(scheme, mesh), target, options);
  EXPECT_TRUE(r.converged);
  EXPECT_LE(r.residual, 1e-9);
  EXPECT_LE(r.iterations, max_iterations)
      << mesh_name << " " << to_string(g) << " " << to_string(scheme)
      << ": Newton should converge quadratically";
  std::printf("[ newton   ] %-16s %-10s %-18s %d iterations, max |K - Kbar| = %.1e\n",
              mesh_name.c_str(), to_string(g).c_str(), to_string(scheme).c_str(), r.iterations,
              r.residual);
  ::testing::Test::RecordProperty(mesh_name + "_" + to_string(g) + "_" + to_string(scheme),
                                  r.iterations);
  expect_gauss_bonnet(mesh, g, r);
  EXPECT_GE(r.num_analyses, 1);
  // A pattern after flips is analysed in the last one's ordering and, where that fills more than
  // kReusedOrderFill times a fresh one's, again afresh (StepSolver): at most twice.
  EXPECT_LE(r.num_analyses, 2 * (1 + r.connectivity_changes))
      << "symbolic factorization at most twice per connectivity";
  // Each iteration factorizes H, or solves with an earlier factorization as MINRES's
  // preconditioner (StepSolver::solve).
  EXPECT_GE(r.num_factorizations, 1);
  EXPECT_GE(r.num_factorizations + r.krylov_iterations, r.iterations);
  return r;
}

// Radius from u by the geometry's own formula, written out here independently of the library.
double radius_of(Geometry g, double u) {
  if (g == Geometry::Euclidean) return std::exp(u);
  if (g == Geometry::Hyperbolic) return 2 * std::atanh(std::exp(u));
  return 2 * std::atan(std::exp(u));
}

TEST(RicciFlow, EverySchemeConvergesOnDisksInE2) {
  const std::map<std::string, CompactMesh> meshes = {
      {"bumpy_disk", test::bumpy_disk(16)}, {"nefertiti", test::cgal_mesh("nefertiti.off")}};
  for (const auto& [name, mesh] : meshes) {
    for (Scheme s : kSchemes) {
      const FlowResult r = expect_converges(name, mesh, Geometry::Euclidean, s,
                                            TargetCurvature::free_boundary(mesh), 8);
      // Free boundary: u keeps its initial value on the boundary, so boundary lengths of the
      // schemes that reproduce the input stay those of the input.
      if (reproduces_input_lengths(s)) {
        for (int e = 0; e < mesh.num_edges(); ++e) {
          if (mesh.is_boundary_edge(e)) {
            EXPECT_NEAR(r.edge_lengths[e] / mesh.input_lengths()[e], 1.0, 1e-12);
          }
        }
      }
      for (int v = 0; v < mesh.num_vertices(); ++v) {
        EXPECT_EQ(std::isnan(r.target[v]), mesh.is_boundary_vertex(v));
      }
    }
  }
}

// Near the solution, an earlier factorization of H preconditions MINRES on the current H (inexact
// Newton): fewer factorizations than iterations, the same tolerance, still few iterations.
TEST(RicciFlow, NearTheSolutionAnEarlierFactorizationServesTheStep) {
  const CompactMesh mesh = test::cgal_mesh("nefertiti.off");
  FlowOptions options;
  options.tolerance = 1e-10;
  const FlowResult r =
      compute_ricci_flow(mesh, Geometry::Euclidean, test::scheme_options(Scheme::Yamabe, mesh),
                         TargetCurvature::free_boundary(mesh), options);
  ASSERT_TRUE(r.converged);
  EXPECT_LE(r.residual, 1e-10);
  EXPECT_LE(r.iterations, 8);
  EXPECT_LT(r.num_factorizations, r.iterations);
  EXPECT_GT(r.krylov_iterations, 0);
  // Each MINRES solve is short: at most StepSolver::kStaleSolveIterations per iteration.
  EXPECT_LE(r.krylov_iterations, detail::StepSolver::kStaleSolveIterations * r.iterations);
  for (size_t i = 1; i < r.residual_history.size(); ++i)
    EXPECT_LT(r.residual_history[i], r.residual_history[i - 1]);
  expect_gauss_bonnet(mesh, Geometry::Euclidean, r);
}

// A step cut short where a longer trial point degenerates triangles leaves Newton in its regime:
// the held factorization preconditions the next step (CGAL's anchor.off, genus 4, in H2 by the
// defaults: 13 iterations and 12 factorizations when each such step was followed by a new
// factorization, 9 and 7 since).
TEST(RicciFlow, StepsBlockedByInvalidTrianglesKeepTheirFactorization) {
  const CompactMesh mesh = test::cgal_mesh("anchor.off");
  const Uniformization run = uniformize(mesh, UniformizationOptions());
  const FlowResult& r = run.result;
  ASSERT_TRUE(r.converged) << r.failure;
  EXPECT_EQ(run.geometry, Geometry::Hyperbolic);
  EXPECT_LE(r.residual, 1e-10);
  ASSERT_EQ(r.residual_history.size(), r.step_history.size() + 1);
  // Steps were cut short, and the flow converged with 9 factorizations at most (12 before).
  EXPECT_GE(std::count_if(r.step_history.begin(), r.step_history.end(),
                          [](double alpha) { return alpha < 1; }),
            3);
  EXPECT_LE(r.num_factorizations, 9);
  EXPECT_LT(r.num_factorizations, r.iterations);
  EXPECT_GT(r.krylov_iterations, 0);
}

// Which runs of accepted steps start edge flips by default (EdgeFlips::WhenNeeded).
TEST(StallWindow, FlipsAreCalledForByStepsCutEverShorterOrBouncing) {
  // Each step: its length, and whether degenerating triangles cut it (negative here).
  const auto first_call = [](const std::vector<double>& steps) {
    detail::StallWindow window;
    std::vector<double> residuals = {1};
    for (size_t i = 0; i < steps.size(); ++i) {
      detail::LineSearch step;
      step.alpha = std::abs(steps[i]);
      step.blocked_by_validity = steps[i] < 0;
      residuals.push_back(0.9 * residuals.back());
      window.stalled(step, residuals);
      if (!window.flips_called_for().empty()) return static_cast<int>(i);
    }
    return -1;
  };
  // qtdv-oilrig.obj, which converges without flips: cut steps that grow again.
  EXPECT_EQ(first_call({1, 1, 1, 1, -0.125, -0.0625, -0.125, -0.25, -0.5, 1, 1, 1, 1}), -1);
  // Cut ever shorter (cow.off).
  EXPECT_EQ(first_call({-0.125, -0.0625, -0.03125, -0.03125}), 3);
  // geomview-hook.off's disk, which converges without flips: cut to 1/8 twice, then recovering.
  EXPECT_EQ(first_call({1, -0.5, -0.5, -0.5, -0.25, -0.25, -0.125, -0.125, -0.03125, 1, 1}), -1);
  // Bouncing off the valid set's boundary (homer.off).
  EXPECT_EQ(first_call({1, -0.5, 1, -0.25, 1, -0.25}), 5);
  // Bounces more than six steps apart.
  EXPECT_EQ(first_call({1, -0.25, 1, 1, 1, 1, 1, -0.25}), -1);
  // Two steps in a row of at most 1/64.
  EXPECT_EQ(first_call({-1.0 / 64, -1.0 / 128}), 1);
  // Steps the residual cut (Armijo), not the triangles.
  EXPECT_EQ(first_call({0.125, 0.0625, 0.03125, 1, 0.25, 1, 0.25, 1.0 / 128, 1.0 / 256}), -1);
}

// Where the flow on the double follows, steps cut short where a boundary triangle stayed invalid
// after the trial points' Ptolemy flips stall the flow after 3 of them with the residual down by
// less than a tenth: no flip of the surface mends that triangle. Without flips tried, 10.
TEST(StallWindow, TrianglesAtTheBoundaryAfterFlipsStallSooner) {
  const auto stalled_at = [](bool after_flips, double progress, bool double_next = true) {
    detail::StallWindow window;
    std::vector<double> residuals = {1};
    for (int i = 0; i < 20; ++i) {
      detail::LineSearch step;
      step.alpha = 1.0 / 128;
      step.blocked_by_validity = step.blocked_at_boundary = true;
      step.blocked_at_boundary_after_flips = after_flips;
      residuals.push_back(progress * residuals.back());
      if (window.stalled(step, residuals, double_next)) return std::make_pair(i, window.window());
    }
    return std::make_pair(-1, 0);
  };
  EXPECT_EQ(stalled_at(true, 0.99), std::make_pair(2, detail::StallWindow::kLoopLength));
  EXPECT_EQ(stalled_at(false, 0.99), std::make_pair(9, detail::StallWindow::kLength));
  // Short steps that take a tenth off the residual over three go on, and are no stall where they
  // halve it over ten.
  EXPECT_EQ(stalled_at(true, 0.94), std::make_pair(9, detail::StallWindow::kLength));
  EXPECT_EQ(stalled_at(true, 0.9).first, -1);
  // Where nothing better follows the stall, 10 too.
  EXPECT_EQ(stalled_at(true, 0.99, false), std::make_pair(9, detail::StallWindow::kLength));
}

TEST(RicciFlow, EverySchemeConvergesOnTorusInE2) {
  const CompactMesh mesh = test::torus(24, 12);
  for (Scheme s : kSchemes) {
    const FlowResult r =
        expect_converges("torus", mesh, Geometry::Euclidean, s, TargetCurvature::zero(mesh), 8);
    // E2 gauge: the result is scaled to the input's area.
    EXPECT_NEAR(r.area / mesh.input_area(), 1.0, 1e-10);
  }
}

TEST(RicciFlow, EverySchemeConvergesOnGenusTwoInH2) {
  const CompactMesh mesh = test::cgal_mesh("eight.off");
  for (Scheme s : kSchemes) {
    const FlowResult r =
        expect_converges("eight", mesh, Geometry::Hyperbolic, s, TargetCurvature::zero(mesh), 8);
    EXPECT_NEAR(r.area, 4 * kPi, 1e-8);  // -2 pi chi
  }
}

TEST(RicciFlow, EverySchemeConvergesOnGenusZeroInS2) {
  const std::map<std::string, CompactMesh> meshes = {
      {"ellipsoid", test::ellipsoid(3, 1.0, 0.8, 0.7)}, {"sphere", test::cgal_mesh("sphere.off")}};
  for (const auto& [name, mesh] : meshes) {
    for (Scheme s : kSchemes) {
      const FlowResult r =
          expect_converges(name, mesh, Geometry::Spherical, s, TargetCurvature::zero(mesh), 10);
      EXPECT_NEAR(r.area, 4 * kPi, 1e-8);
    }
  }
}

TEST(RicciFlow, YamabePreservesLengthCrossRatios) {
  // On a fixed triangulation l_ij = e^((ui+uj)/2) L_ij: every interior edge's quadrilateral
  // keeps its length cross-ratio. (With flips, see delaunay_test.cpp.)
  const CompactMesh mesh = test::cgal_mesh("nefertiti.off");
  const FlowResult r =
      compute_ricci_flow(mesh, Geometry::Euclidean, test::scheme_options(Scheme::Yamabe, mesh),
                         TargetCurvature::free_boundary(mesh), test::without_flips());
  auto cross_ratio = [&](const std::vector<double>& l, int h) {
    const int t = mesh.twin(h);
    const int f = h / 3, g = t / 3, c = h % 3, d = t % 3;
    // Face f: edges (c+1), (c+2) around; face g likewise.
    return (l[mesh.face_edge(f, (c + 1) % 3)] * l[mesh.face_edge(g, (d + 1) % 3)]) /
           (l[mesh.face_edge(f, (c + 2) % 3)] * l[mesh.face_edge(g, (d + 2) % 3)]);
  };
  int checked = 0;
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    if (mesh.twin(h) < 0) continue;
    EXPECT_NEAR(cross_ratio(r.edge_lengths, h) / cross_ratio(mesh.input_lengths(), h), 1.0, 1e-9);
    ++checked;
  }
  EXPECT_GT(checked, 1000);
  // And the result really moved away from the input.
  double max_change = 0;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    max_change = std::max(max_change, std::abs(r.edge_lengths[e] / mesh.input_lengths()[e] - 1));
  }
  EXPECT_GT(max_change, 0.1);
}

TEST(RicciFlow, TangentialPackingsTouchInEveryGeometry) {
  struct Case {
    Geometry g;
    CompactMesh mesh;
  };
  const Case cases[] = {{Geometry::Euclidean, test::torus(16, 8)},
                        {Geometry::Hyperbolic, test::cgal_mesh("eight.off")},
                        {Geometry::Spherical, test::ellipsoid(2)}};
  for (const auto& c : cases) {
    const FlowResult r =
        compute_ricci_flow(c.mesh, c.g, test::scheme_options(Scheme::Tangential, c.mesh),
                           TargetCurvature::zero(c.mesh), test::without_flips());
    for (int e = 0; e < c.mesh.num_edges(); ++e) {
      const auto [i, j] = c.mesh.edge_vertices(e);
      EXPECT_NEAR(r.edge_lengths[e], radius_of(c.g, r.u[i]) + radius_of(c.g, r.u[j]),
                  1e-12 * (1 + r.edge_lengths[e]));
    }
  }
}

TEST(RicciFlow, InversiveDistanceIsPreserved) {
  // The classical inversive distance of two circles, from the result's lengths and radii:
  //   E2: l^2 = ri^2 + rj^2 + 2 I ri rj;  H2: cosh l = cosh ri cosh rj + I sinh ri sinh rj;
  //   S2: cos l = cos ri cos rj - I sin ri sin rj.  It must equal the initial eta.
  struct Case {
    Geometry g;
    CompactMesh mesh;
  };
  const Case cases[] = {{Geometry::Euclidean, test::cgal_mesh("nefertiti.off")},
                        {Geometry::Hyperbolic, test::cgal_mesh("eight.off")},
                        {Geometry::Spherical, test::ellipsoid(2, 1.0, 0.9, 0.8)}};
  for (const auto& c : cases) {
    const SchemeOptions options = test::scheme_options(Scheme::InversiveDistance, c.mesh);
    const TargetCurvature target = TargetCurvature::free_boundary_or_zero(c.mesh);
    const ConformalStructure s = prepare_flow(c.mesh, c.g, options, target);
    const FlowResult r = run_ricci_flow(c.mesh, s, target, test::without_flips());
    ASSERT_TRUE(r.converged) << r.failure;
    for (int e = 0; e < c.mesh.num_edges(); ++e) {
      const auto [i, j] = c.mesh.edge_vertices(e);
      const double ri = radius_of(c.g, r.u[i]), rj = radius_of(c.g, r.u[j]), l = r.edge_lengths[e];
      double inversive;
      if (c.g == Geometry::Euclidean) {
        inversive = (l * l - ri * ri - rj * rj) / (2 * ri * rj);
      } else if (c.g == Geometry::Hyperbolic) {
        inversive =
            (std::cosh(l) - std::cosh(ri) * std::cosh(rj)) / (std::sinh(ri) * std::sinh(rj));
      } else {
        inversive = (std::cos(ri) * std::cos(rj) - std::cos(l)) / (std::sin(ri) * std::sin(rj));
      }
      EXPECT_NEAR(inversive / s.eta[e], 1.0, 1e-8) << to_string(c.g) << " edge " << e;
    }
  }
}

TEST(RicciFlow, PrescribedBoundaryCurvatureOnADisk) {
  // Every boundary vertex gets an equal share of 2 pi, interior flat: a disk-like polygon.
  const CompactMesh mesh = test::bumpy_disk(12);
  TargetCurvature target = TargetCurvature::zero(mesh);
  int nb = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) nb += mesh.is_boundary_vertex(v);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.is_boundary_vertex(v)) target.curvature[v] = 2 * kPi / nb;
  }
  const FlowResult r =
      expect_converges("bumpy_disk", mesh, Geometry::Euclidean, Scheme::Yamabe, target, 10);
  for (int v = 0; v < mesh.num_vertices(); ++v) EXPECT_FALSE(std::isnan(r.target[v]));
}

TEST(RicciFlow, LdltAndCholmodAgree) {
  const CompactMesh mesh = test::cgal_mesh("nefertiti.off");
  FlowOptions cholmod, ldlt;
  ldlt.linear_solver = LinearSolverKind::Ldlt;
  const auto target = TargetCurvature::free_boundary(mesh);
  const FlowResult a = compute_ricci_flow(
      mesh, Geometry::Euclidean, test::scheme_options(Scheme::Yamabe, mesh), target, cholmod);
  const FlowResult b = compute_ricci_flow(mesh, Geometry::Euclidean,
                                          test::scheme_options(Scheme::Yamabe, mesh), target, ldlt);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_LE((a.u - b.u).cwiseAbs().maxCoeff(), 1e-10);
}

}  // namespace
}  // namespace ricci
