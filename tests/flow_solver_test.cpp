// RicciFlowSolver's behaviour around the algorithm: what a result records, the attainable floor,
// resuming, cancelling, limits, and failures explained.
#include "ricci/flow/ricci_flow.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "flow/delaunay.h"
#include "flow/flow_steps.h"
#include "flow/metric.h"
#include "pipeline/texture_atlas.h"
#include "ricci/flow/cone_placement.h"
#include "ricci/flow/presets.h"
#include "ricci/io/mesh_io.h"
#include "ricci/mesh/errors.h"
#include "ricci/repair/repair.h"
#include "test_meshes.h"

namespace ricci {
namespace {

TEST(RicciFlow, ResultHasHistoryAndTimings) {
  const CompactMesh mesh = test::bumpy_disk(10);
  int calls = 0;
  FlowOptions options;
  options.progress = [&](const FlowProgress&) { return ++calls > 0; };
  const FlowResult r =
      compute_ricci_flow(mesh, Geometry::Euclidean, test::scheme_options(Scheme::Yamabe, mesh),
                         TargetCurvature::free_boundary(mesh), options);
  EXPECT_EQ(static_cast<int>(r.residual_history.size()), r.iterations + 1);
  EXPECT_EQ(static_cast<int>(r.step_history.size()), r.iterations);
  EXPECT_EQ(calls, r.iterations + 1);
  // The merit line search makes the residual fall at every iteration.
  for (size_t i = 1; i < r.residual_history.size(); ++i) {
    EXPECT_LT(r.residual_history[i], r.residual_history[i - 1]);
  }
  EXPECT_GT(r.times.total, 0.0);
  EXPECT_GE(r.times.total, r.times.factorization);
}

TEST(RicciFlow, AToleranceBelowDoublePrecisionConvergesAtTheAttainableFloor) {
  // 1e-18 is below what the angle sums' round-off allows on a real scan: the flow goes on until
  // no step reduces the residual, and counts as converged there, saying within what.
  const CompactMesh mesh = test::cgal_mesh("nefertiti.off");
  const TargetCurvature target = TargetCurvature::free_boundary(mesh);
  const ConformalStructure s = prepare_flow(mesh, Geometry::Euclidean, {}, target);
  FlowOptions tight;
  tight.tolerance = 1e-18;
  const FlowResult r = run_ricci_flow(mesh, s, target, tight);
  ASSERT_TRUE(r.converged) << r.failure;
  EXPECT_GT(r.attainable_residual, tight.tolerance);
  EXPECT_LT(r.attainable_residual, 1e-11);
  EXPECT_LE(r.residual, r.attainable_residual);
  // At the usual tolerance, the tolerance itself is reached.
  const FlowResult usual = run_ricci_flow(mesh, s, target);
  ASSERT_TRUE(usual.converged);
  EXPECT_EQ(usual.attainable_residual, 0);
  // A genuine stall is no floor: the input's triangulation of a scan (elk.off, a torus) without
  // flips stops far above it.
  const CompactMesh elk = test::cgal_mesh("elk.off");
  FlowOptions fixed;
  fixed.edge_flips = EdgeFlips::Never;
  const TargetCurvature zero = TargetCurvature::zero(elk);
  const FlowResult stalled =
      run_ricci_flow(elk, prepare_flow(elk, Geometry::Euclidean, {}, zero), zero, fixed);
  EXPECT_FALSE(stalled.converged);
  EXPECT_EQ(stalled.attainable_residual, 0);
}

TEST(RicciFlow, ThePinnedGaugeVertexCarriesTheOthersRoundOff) {
  // A flat torus (E2, no fixed vertex): vertex 0 is pinned against the scaling, and its residual
  // is minus the sum of all the others' (Gauss-Bonnet), so their round-off adds up there. At a
  // tolerance below double precision the flow converges at the floor all the same.
  const CompactMesh mesh = test::torus(160, 120);
  const TargetCurvature target = TargetCurvature::zero(mesh);
  FlowOptions tight;
  tight.tolerance = 1e-18;
  const FlowResult r =
      run_ricci_flow(mesh, prepare_flow(mesh, Geometry::Euclidean, {}, target), target, tight);
  ASSERT_TRUE(r.converged) << r.failure;
  EXPECT_GT(r.attainable_residual, 0);
  EXPECT_LE(r.residual, r.attainable_residual);
  EXPECT_LT(r.attainable_residual, 1e-9);
  std::printf("[ floor    ] %d vertices: residual %.3g (vertex 0: %.3g), floor %.3g\n",
              mesh.num_vertices(), r.residual, std::abs(r.curvature[0]), r.attainable_residual);
}

TEST(RicciFlow, SolverResumesFromItsLastResult) {
  // The disk target's second flow (presets.h): boundary curvature refitted to circles through the
  // first result's boundary chords, a target near the first. Resumed from the first result (a real
  // scan whose flow flipped edges), it takes fewer iterations and reaches the cold start's u.
  const CompactMesh mesh = test::cgal_mesh("nefertiti.off");
  const int outer = outer_boundary_loop(mesh, mesh.input_lengths());
  const TargetCurvature target1 = circle_boundary_target(mesh, mesh.input_lengths(), outer);
  const ConformalStructure s = prepare_flow(mesh, Geometry::Euclidean, {}, target1);
  FlowOptions always;
  always.edge_flips = EdgeFlips::Always;
  RicciFlowSolver solver(mesh, s, always);
  const FlowResult first = solver.solve(target1);
  ASSERT_TRUE(first.converged);
  ASSERT_GT(first.num_flips, 0);
  const TargetCurvature target2 =
      circle_boundary_target(result_triangulation(mesh, first), first.edge_lengths, outer);
  const FlowResult cold = run_ricci_flow(mesh, s, target2, always);
  const FlowResult warm = solver.solve(target2);
  ASSERT_TRUE(cold.converged) << cold.failure;
  ASSERT_TRUE(warm.converged) << warm.failure;
  EXPECT_LT(warm.iterations, cold.iterations);
  EXPECT_LE(warm.num_analyses, cold.num_analyses);
  EXPECT_LE((warm.u - cold.u).cwiseAbs().maxCoeff(), 1e-8);
  // The flips replay from the input: the sequence starts with the first flow's.
  ASSERT_GE(warm.flip_sequence.size(), first.flip_sequence.size());
  EXPECT_TRUE(std::equal(first.flip_sequence.begin(), first.flip_sequence.end(),
                         warm.flip_sequence.begin(),
                         [](const EdgeFlip& x, const EdgeFlip& y) { return x.edge == y.edge; }));
  ASSERT_TRUE(warm.triangulation.has_value());
}

// The atlas's flow at BFF's 8 cones on a mesh: the cones, their target and structure, and the
// input's intrinsic Delaunay triangulation with its class (where the flow's flips begin).
struct AtEightCones {
  ConePlacement placement;
  TargetCurvature target;
  ConformalStructure structure;
  IntrinsicTriangulation input_delaunay;
  ConformalStructure input_class;
};

AtEightCones at_eight_cones(const CompactMesh& mesh) {
  ConePlacementOptions o;
  o.max_cones = 8;
  ConePlacement p = place_cones(mesh, o);
  EXPECT_EQ(p.cones.size(), 8u);
  TargetCurvature target = detail::atlas_target(mesh, p, false);
  ConformalStructure s = prepare_flow(mesh, Geometry::Euclidean, {}, target);
  AtEightCones e{std::move(p), std::move(target), s, IntrinsicTriangulation(mesh), s};
  make_input_delaunay(e.input_delaunay, e.input_class);
  return e;
}

// The flow with flips from u = 0 and from the linear model's u, both converged to one metric.
std::pair<FlowResult, FlowResult> cold_and_warm(const CompactMesh& mesh, const AtEightCones& e) {
  FlowOptions always;
  always.edge_flips = EdgeFlips::Always;
  FlowResult cold = run_ricci_flow(mesh, e.structure, e.target, always);
  RicciFlowSolver solver(mesh, e.structure, always);
  FlowResult warm = solver.solve(e.target, &e.placement.u);
  EXPECT_TRUE(cold.converged) << cold.failure;
  EXPECT_TRUE(warm.converged) << warm.failure;
  EXPECT_LE((warm.u - cold.u).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LE((warm.curvature - cold.curvature).cwiseAbs().maxCoeff(), 1e-9);
  return {std::move(cold), std::move(warm)};
}

TEST(RicciFlow, AStartReachedByPtolemyFlipsGivesTheColdStartsMetric) {
  // The atlas's flow at 8 cones, from the linear model's u: invalid triangles on the input's
  // Delaunay triangulation, valid on the start's own (Ptolemy flips from the lengths), where
  // Newton begins. It converges in fewer iterations to the cold start's metric.
  const CompactMesh mesh = test::cgal_mesh("camel.off");
  const AtEightCones e = at_eight_cones(mesh);
  ASSERT_FALSE(evaluate_metric(e.input_delaunay, e.input_class, e.placement.u).valid());
  const auto [cold, warm] = cold_and_warm(mesh, e);
  EXPECT_LT(warm.iterations, cold.iterations);
  EXPECT_EQ(warm.eased_start_vertices, 0);
  FlowOptions no_newton;
  no_newton.edge_flips = EdgeFlips::Always;
  no_newton.max_iterations = 0;
  RicciFlowSolver at_start(mesh, e.structure, no_newton);
  const FlowResult begun = at_start.solve(e.target, &e.placement.u);
  ASSERT_EQ(begun.u.size(), e.placement.u.size());
  EXPECT_EQ((begun.u - e.placement.u).cwiseAbs().maxCoeff(), 0);
  EXPECT_GT(begun.num_flips, 0);
  std::printf("[ start    ] camel at 8 cones: %d iterations from the start (%d flips), %d cold\n",
              warm.iterations, warm.num_flips, cold.iterations);
}

TEST(RicciFlow, AStartWhoseDelaunayTriangulationNeedsALoopIsEasedToTheColdStartsMetric) {
  // PyMeshLab's cow at 8 cones: the linear model puts a vertex of a horn at u = -10 among
  // neighbours at -4 to -5, which the start's Delaunay triangulation would enclose in an edge
  // from a vertex to itself; the Ptolemy flips to it leave invalid triangles. The start is eased
  // at a few free vertices instead of walked to, and Newton converges to the cold start's metric.
  const CompactMesh mesh = read_mesh(RICCI_REAL_MESH_DIR "/pymeshlab-cow.obj");
  AtEightCones e = at_eight_cones(mesh);
  MetricState at_start = evaluate_metric(e.input_delaunay, e.input_class, e.placement.u);
  ASSERT_FALSE(at_start.valid());
  const FlipReport flips = make_delaunay(e.input_delaunay, e.input_class, e.placement.u, at_start,
                                         10 * mesh.num_edges(), false);
  EXPECT_GT(flips.blocked, 0);
  EXPECT_FALSE(at_start.valid()) << "the start's own triangulation needs no loop";
  const auto [cold, warm] = cold_and_warm(mesh, e);
  EXPECT_GT(warm.eased_start_vertices, 0);
  EXPECT_LT(warm.eased_start_vertices, 20);
  EXPECT_EQ(cold.eased_start_vertices, 0);
  std::printf("[ eased    ] cow at 8 cones: %d vertices eased, %d iterations (%d cold)\n",
              warm.eased_start_vertices, warm.iterations, cold.iterations);
}

TEST(RicciFlow, EasingsThatLeaveNoFewerInvalidFacesStopAsHopeless) {
  // At 8 cones occt-tr12j's start (genus 22) is far off everywhere, not at a few spike tips: the
  // jumps to it leave 771 to 1531 invalid faces however it is eased, and the flow walks there.
  // The easings stop after kEasingsWithoutProgress (5) in a row with no fewer invalid faces than
  // the fewest before (the jumps were 13; a walk made again, finish_walk, would jump once more).
  // CGAL's femur's easings go on past three such and end valid: the start eased at some vertices
  // is taken.
  struct Case {
    std::string path;
    bool taken;
  };
  for (const Case& c : {Case{RICCI_REAL_MESH_DIR "/occt-tr12j.stl", false},
                        Case{test::cgal_mesh_path("femur.off"), true}}) {
    const MeshFile file = read_mesh_file(c.path);
    const RepairedMesh repaired = repair_mesh(file.positions, file.triangles);
    ASSERT_EQ(repaired.components.size(), 1u) << c.path;
    const CompactMesh& mesh = repaired.components[0].mesh;
    const AtEightCones e = at_eight_cones(mesh);
    FlowOptions o;
    o.edge_flips = EdgeFlips::Always;
    o.start_is_a_step = true;
    RicciFlowSolver solver(mesh, e.structure, o);
    const FlowResult r = solver.solve(e.target, &e.placement.u);
    ASSERT_TRUE(r.converged) << c.path << ": " << r.failure;
    if (c.taken) {
      EXPECT_GT(r.eased_start_vertices, 0) << c.path;
      EXPECT_GT(r.start_jumps, 6) << c.path;
    } else {
      EXPECT_EQ(r.eased_start_vertices, 0) << c.path;
      EXPECT_EQ(r.start_jumps, 6) << c.path;
    }
    std::printf("[ easings  ] %s at 8 cones: %d jumps, %d vertices eased, %d iterations\n",
                c.path.c_str(), r.start_jumps, r.eased_start_vertices, r.iterations);
  }
}

TEST(RicciFlow, AStartThatIsNewtonsFirstStepIsHalvedWhereItRaisesTheResidual) {
  // CGAL's bull at 8 cones of up to two turns: the linear model's u leaves a squared residual
  // above u = 0's. Taken as Newton's first step (FlowOptions::start_is_a_step) it is halved, and
  // Newton converges in fewer iterations to the metric of the whole step. The camel's linear model
  // lowers the residual: its start is taken whole, the flow as without the option.
  for (const char* name : {"bull.off", "camel.off"}) {
    const CompactMesh mesh = test::cgal_mesh(name);
    const AtEightCones e = at_eight_cones(mesh);
    FlowOptions o;
    o.edge_flips = EdgeFlips::Always;
    RicciFlowSolver whole_solver(mesh, e.structure, o);
    const FlowResult whole = whole_solver.solve(e.target, &e.placement.u);
    o.start_is_a_step = true;
    RicciFlowSolver step_solver(mesh, e.structure, o);
    const FlowResult step = step_solver.solve(e.target, &e.placement.u);
    ASSERT_TRUE(whole.converged) << name << ": " << whole.failure;
    ASSERT_TRUE(step.converged) << name << ": " << step.failure;
    EXPECT_LE((step.u - whole.u).cwiseAbs().maxCoeff(), 1e-8) << name;
    if (std::string(name) == "bull.off") {
      EXPECT_LT(step.start_share, 1);
      EXPECT_LT(step.iterations, whole.iterations);
    } else {
      EXPECT_EQ(step.start_share, 1);
      EXPECT_EQ(step.iterations, whole.iterations);
    }
    std::printf("[ start    ] %s at 8 cones: share %g, %d iterations (%d from the whole step)\n",
                name, step.start_share, step.iterations, whole.iterations);
  }
}

TEST(RicciFlow, AConvergedFlowSaysWhereItsDelaunayFlipsRefusedALoop) {
  // Gymnasium's Adroit shoulder (its genus-7 part of 10.9k faces) at 8 cones of 1.6 to 2.8 turns:
  // the flow converges, but the last Delaunay flips refused some flips to an edge from a vertex to
  // itself, and the triangulation it ends on is no Delaunay triangulation there (its layout turned
  // faces of the subdivision over, and the atlas flowed the cones again with loops). With loops
  // the same flow ends on a triangulation that has some, and refuses none. From half the linear
  // model's step (start_is_a_step, the atlas's since 2026-12-07) it converges in fewer iterations,
  // refusing loops as well, on another triangulation that is not Delaunay where they were refused,
  // so to another u (by 4e-3; the atlas's layout of it turns no face: atlas_test).
  const MeshFile file = read_mesh_file(RICCI_REAL_MESH_DIR "/gymrobotics-adroit-shoulder.stl");
  const RepairedMesh repaired = repair_mesh(file.positions, file.triangles);
  ASSERT_FALSE(repaired.components.empty());
  const CompactMesh& mesh = repaired.components[0].mesh;
  ASSERT_EQ(mesh.genus(), 7) << "this mesh no longer shows the case";
  const AtEightCones e = at_eight_cones(mesh);
  FlowOptions options;
  options.edge_flips = EdgeFlips::Always;
  const FlowResult without =
      RicciFlowSolver(mesh, e.structure, options).solve(e.target, &e.placement.u);
  ASSERT_TRUE(without.converged) << without.failure;
  EXPECT_FALSE(without.stalled_for_loops);
  EXPECT_GT(without.loops_refused, 0);
  options.loops = true;
  const FlowResult with =
      RicciFlowSolver(mesh, e.structure, options).solve(e.target, &e.placement.u);
  ASSERT_TRUE(with.converged) << with.failure;
  EXPECT_EQ(with.loops_refused, 0);
  const Triangulation& flowed = result_triangulation(mesh, with);
  int loops = 0;
  for (int edge = 0; edge < flowed.num_edges(); ++edge)
    loops += flowed.edge_vertices(edge)[0] == flowed.edge_vertices(edge)[1];
  EXPECT_GT(loops, 0);
  options.loops = false;
  options.start_is_a_step = true;
  const FlowResult halved =
      RicciFlowSolver(mesh, e.structure, options).solve(e.target, &e.placement.u);
  ASSERT_TRUE(halved.converged) << halved.failure;
  EXPECT_LT(halved.start_share, 1);
  EXPECT_LT(halved.iterations, without.iterations);
  std::printf(
      "[ loops    ] shoulder at 8 cones: %d refused without loops (%d iterations); %d made "
      "with them; from %g of the step %d refused (%d iterations)\n",
      without.loops_refused, without.iterations, loops, halved.start_share, halved.loops_refused,
      halved.iterations);
}

TEST(RicciFlow, CancelStopsTheFlow) {
  const CompactMesh mesh = test::bumpy_disk(10);
  FlowOptions options;
  options.progress = [](const FlowProgress& p) { return p.iteration < 1; };
  const auto target = TargetCurvature::free_boundary(mesh);
  const ConformalStructure s =
      prepare_flow(mesh, Geometry::Euclidean, test::scheme_options(Scheme::Yamabe, mesh), target);
  const FlowResult r = run_ricci_flow(mesh, s, target, options);
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.failure.find("cancelled"), std::string::npos);
}

TEST(RicciFlow, IterationLimitIsReported) {
  const CompactMesh mesh = test::cgal_mesh("nefertiti.off");
  FlowOptions options;
  options.max_iterations = 1;
  try {
    compute_ricci_flow(mesh, Geometry::Euclidean, test::scheme_options(Scheme::Yamabe, mesh),
                       TargetCurvature::free_boundary(mesh), options);
    FAIL() << "expected ConvergenceError";
  } catch (const ConvergenceError& e) {
    EXPECT_NE(std::string(e.what()).find("no convergence in 1 iterations"), std::string::npos)
        << e.what();
    EXPECT_EQ(e.iterations(), 1);
    EXPECT_GT(e.residual(), 1e-10);
  }
}

TEST(RicciFlow, StallOnARealMeshIsExplained) {
  // A torus scan on a fixed triangulation: Yamabe runs into degenerate triangles (DESIGN.md).
  const CompactMesh mesh = test::cgal_mesh("elk.off");
  try {
    compute_ricci_flow(mesh, Geometry::Euclidean, test::scheme_options(Scheme::Yamabe, mesh),
                       TargetCurvature::zero(mesh), test::without_flips());
    FAIL() << "expected ConvergenceError";
  } catch (const ConvergenceError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("stalled at iteration"), std::string::npos) << m;
    EXPECT_NE(m.find("degenerat"), std::string::npos) << m;
    EXPECT_LT(e.iterations(), 100);
  }
  // The tangential packing, whose triangles are always valid, converges on the same mesh, and
  // so does Yamabe with edge flips.
  const FlowResult r =
      compute_ricci_flow(mesh, Geometry::Euclidean, test::scheme_options(Scheme::Tangential, mesh),
                         TargetCurvature::zero(mesh), test::without_flips());
  EXPECT_TRUE(r.converged);
  const FlowResult flipped =
      compute_ricci_flow(mesh, Geometry::Euclidean, test::scheme_options(Scheme::Yamabe, mesh),
                         TargetCurvature::zero(mesh));
  EXPECT_TRUE(flipped.converged);
  EXPECT_GT(flipped.num_flips, 0);
}

TEST(RicciFlow, TopologyThatCannotCarryTheGeometryIsRefusedUpFront) {
  const CompactMesh torus = test::torus(10, 6);
  EXPECT_THROW(
      compute_ricci_flow(torus, Geometry::Spherical, test::scheme_options(Scheme::Yamabe, torus),
                         TargetCurvature::zero(torus)),
      InvalidTargetError);
  EXPECT_THROW(
      compute_ricci_flow(torus, Geometry::Hyperbolic, test::scheme_options(Scheme::Yamabe, torus),
                         TargetCurvature::zero(torus)),
      InvalidTargetError);
}

}  // namespace
}  // namespace ricci
