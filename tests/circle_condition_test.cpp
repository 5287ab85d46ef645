// Boundary loops on circles in one Newton solve: the circle condition's derivative against
// differences, MINRES against dense solves, and the one-solve flow against the repeated flows of
// the fixed-point iteration (the same map onto the disk, up to the disk's Moebius maps).
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "flow/circle_condition.h"
#include "linear/minres.h"
#include "pipeline/circle_domain.h"
#include "ricci/flow/presets.h"
#include "ricci/flow/ricci_flow.h"
#include "ricci/layout/lay_out.h"
#include "ricci/layout/layout.h"
#include "ricci/mesh/errors.h"
#include "test_meshes.h"

namespace ricci {
namespace {

// Euclidean Yamabe lengths at u: l_e = l0_e exp((u_a + u_b) / 2).
std::vector<double> yamabe_lengths(const CompactMesh& mesh, const Eigen::VectorXd& u) {
  std::vector<double> l = mesh.input_lengths();
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto& ends = mesh.edge_vertices(e);
    l[e] *= std::exp(0.5 * (u[ends[0]] + u[ends[1]]));
  }
  return l;
}

Eigen::VectorXd circle_target(const detail::CircleCondition& circles, const CompactMesh& mesh,
                              const Eigen::VectorXd& u) {
  TargetCurvature t = TargetCurvature::zero(mesh);
  circles.set_target(yamabe_lengths(mesh, u), t);
  return t.curvature;
}

// d target / d u applied to a direction, against central differences, on a disk and on a
// surface with seven boundary loops (the inner ones turning negatively).
TEST(CircleCondition, DerivativeMatchesDifferences) {
  for (const char* name : {"nefertiti.off", "holes.off"}) {
    const CompactMesh mesh = test::cgal_mesh(name);
    const int outer = outer_boundary_loop(mesh, mesh.input_lengths());
    detail::CircleCondition circles(mesh, outer);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-0.3, 0.3);
    Eigen::VectorXd u(mesh.num_vertices()), du(mesh.num_vertices());
    for (int v = 0; v < mesh.num_vertices(); ++v) u[v] = uniform(random), du[v] = uniform(random);
    circles.linearize(yamabe_lengths(mesh, u));
    const Eigen::VectorXd analytic = circles.apply(du);
    const double h = 1e-6;
    const Eigen::VectorXd numeric =
        (circle_target(circles, mesh, u + h * du) - circle_target(circles, mesh, u - h * du)) /
        (2 * h);
    EXPECT_GT(analytic.cwiseAbs().maxCoeff(), 1e-4) << name;
    EXPECT_LE((analytic - numeric).cwiseAbs().maxCoeff(), 1e-6 * analytic.cwiseAbs().maxCoeff())
        << name;
    // The scale changes no circle: constants are in the kernel.
    EXPECT_LE(circles.apply(Eigen::VectorXd::Ones(mesh.num_vertices())).cwiseAbs().maxCoeff(),
              1e-12)
        << name;
    // The same rule as the fixed-point iteration's target.
    TargetCurvature t = TargetCurvature::zero(mesh);
    circles.set_target(mesh.input_lengths(), t);
    EXPECT_EQ(t.curvature, circle_boundary_target(mesh, mesh.input_lengths(), outer).curvature);
  }
}

// Symmetric indefinite systems, one of them singular and consistent, with a symmetric positive
// definite preconditioner: MINRES reaches the dense solution (the minimum-norm one when singular).
TEST(CircleCondition, MinresSolvesSymmetricIndefiniteSystems) {
  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  const int n = 60;
  Eigen::MatrixXd q = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return normal(random); });
  q = q.householderQr().householderQ();
  Eigen::VectorXd eigenvalues(n);
  for (int i = 0; i < n; ++i) eigenvalues[i] = (i % 3 == 0 ? -1.0 : 1.0) * (0.5 + i);
  const Eigen::VectorXd m = Eigen::VectorXd::LinSpaced(n, 1.0, 3.0);
  const auto precondition = [&](const Eigen::VectorXd& r) -> Eigen::VectorXd {
    return r.cwiseQuotient(m);
  };
  for (bool singular : {false, true}) {
    Eigen::VectorXd d = eigenvalues;
    if (singular) d[5] = d[17] = 0;
    const Eigen::MatrixXd a = q * d.asDiagonal() * q.transpose();
    Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(n, [&] { return normal(random); });
    if (singular) b -= q.col(5) * q.col(5).dot(b) + q.col(17) * q.col(17).dot(b);
    const auto apply = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return a * x; };
    const detail::MinresResult r = detail::minres(apply, precondition, b, 1e-12, 500);
    EXPECT_LE(r.relative_residual, 1e-12);
    EXPECT_LE((a * r.x - b).norm(), 1e-9 * b.norm()) << "singular " << singular;
    if (!singular) {
      EXPECT_LE((r.x - a.lu().solve(b)).norm(), 1e-9 * r.x.norm());
    } else {
      // Nothing along the kernel: the Krylov space of M^-1 A holds none of it when M^-1 keeps
      // the kernel out of the range, so compare in the range only.
      const Eigen::VectorXd dense = a.completeOrthogonalDecomposition().solve(b);
      Eigen::VectorXd in_range = r.x;
      for (int k : {5, 17}) in_range -= q.col(k) * q.col(k).dot(r.x);
      EXPECT_LE((in_range - dense).norm(), 1e-8 * dense.norm());
    }
  }
}

// The disk by one solve and by the fixed-point iteration of repeated flows: one flow of a few
// Newton iterations against many, and the same map once both are moved onto the unit disk with
// the same centre and axis vertex.
TEST(CircleCondition, OneSolveGivesTheFixedPointIterationsMap) {
  const CompactMesh disk = test::cgal_mesh("nefertiti.off");
  const int outer = outer_boundary_loop(disk, disk.input_lengths());
  const TargetCurvature target = circle_boundary_target(disk, disk.input_lengths(), outer);
  const ConformalStructure structure = prepare_flow(disk, Geometry::Euclidean, {}, target);
  FlowOptions flow;
  flow.edge_flips = EdgeFlips::Never;
  RicciFlowSolver one(disk, structure, flow);
  const FlowResult direct = one.solve_circle_domain(target, outer);
  ASSERT_TRUE(direct.converged) << direct.failure;
  EXPECT_LE(direct.iterations, 10);
  EXPECT_GT(direct.krylov_iterations, 0);

  RicciFlowSolver repeated(disk, structure, flow);
  UniformizationOptions o;
  Uniformization run;
  detail::fit_boundary_to_circles(repeated, disk, detail::refit_on_mesh(disk, outer), target, o,
                                  run);
  ASSERT_TRUE(run.result.converged) << run.result.failure;
  EXPECT_GT(run.totals.flows, 3);

  int center = 0;
  while (disk.is_boundary_vertex(center)) ++center;
  const std::vector<int>& boundary = disk.boundary_loops()[outer];
  const auto on_disk = [&](const FlowResult& r) {
    const Layout layout = lay_out(disk, Geometry::Euclidean, r.edge_lengths);
    return detail::normalize_to_unit_disk(vertex_positions(disk, layout), boundary, center,
                                          boundary[0]);
  };
  const std::vector<Eigen::Vector3d> a = on_disk(direct), b = on_disk(run.result);
  double distance = 0, off_circle = 0;
  for (int v = 0; v < disk.num_vertices(); ++v) distance = std::max(distance, (a[v] - b[v]).norm());
  for (int v : boundary) off_circle = std::max(off_circle, std::abs(a[v].norm() - 1));
  EXPECT_LE(distance, 1e-7);
  EXPECT_LE(off_circle, 1e-9);
}

// Only the Euclidean Yamabe flow on a surface with boundary, with one of its loops as the outer
// one, takes the one solve.
TEST(CircleCondition, OneSolveRefusesOtherFlows) {
  const CompactMesh disk = test::cgal_mesh("nefertiti.off");
  const int outer = outer_boundary_loop(disk, disk.input_lengths());
  const TargetCurvature target = circle_boundary_target(disk, disk.input_lengths(), outer);
  SchemeOptions tangential;
  tangential.scheme = Scheme::Tangential;
  RicciFlowSolver solver(disk, prepare_flow(disk, Geometry::Euclidean, tangential, target));
  EXPECT_THROW(solver.solve_circle_domain(target, outer), InvalidArgumentError);
  RicciFlowSolver yamabe(disk, prepare_flow(disk, Geometry::Euclidean, {}, target));
  EXPECT_THROW(yamabe.solve_circle_domain(target, disk.num_boundary_loops()), InvalidArgumentError);
}

}  // namespace
}  // namespace ricci
