// The flow with edge flips on real meshes of every topology, thousands to ~90k faces, with sharp
// features (CGAL's CC0 data set): converges to 1e-10 where the fixed triangulation stalls.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "ricci/flow/ricci_flow.h"
#include "ricci/layout/lay_out.h"
#include "ricci/layout/layout.h"
#include "test_meshes.h"

namespace ricci {
namespace {

struct Case {
  std::string mesh;
  int subdivisions;
  Geometry geometry;
  Scheme scheme;
};

class RealMesh : public ::testing::TestWithParam<Case> {};

TEST_P(RealMesh, ConvergesWithFlips) {
  const Case c = GetParam();
  const CompactMesh mesh = test::subdivide_midpoint(test::cgal_mesh(c.mesh), c.subdivisions);
  const SchemeOptions scheme = test::scheme_options(c.scheme, mesh);
  const FlowResult r =
      compute_ricci_flow(mesh, c.geometry, scheme, TargetCurvature::free_boundary_or_zero(mesh));
  EXPECT_TRUE(r.converged);
  EXPECT_LE(r.residual, 1e-10);
  // By default the flow flips only from where the input's triangulation stalled.
  EXPECT_LE(r.iterations - std::max(r.flips_from_iteration, 0), 20);
  EXPECT_NEAR(r.curvature.sum() + background_curvature(c.geometry) * r.area,
              2 * kPi * mesh.euler_characteristic(), 1e-8);
  std::string layout = "";
  if (c.geometry == Geometry::Euclidean && !mesh.is_closed()) {
    const Triangulation& t = result_triangulation(mesh, r);
    const Layout l = lay_out(t, Geometry::Euclidean, r.edge_lengths);
    EXPECT_EQ(l.num_flipped_faces, 0);
    EXPECT_LE(l.max_relative_length_error, 1e-8);
    int flipped = 0;
    for (const auto& face : corners_on(t, l, mesh)) {
      flipped += !(orientation(Geometry::Euclidean, face) > 0);
    }
    layout = ", layout flips " + std::to_string(flipped) + " input faces";
  }
  std::printf(
      "[ flips    ] %-18s %7d faces %-10s %-18s %2d iterations (flips from %2d) %6d flips "
      "%.2f s%s\n",
      c.mesh.c_str(), mesh.num_faces(), to_string(c.geometry).c_str(), to_string(c.scheme).c_str(),
      r.iterations, r.flips_from_iteration, r.num_flips, r.times.total, layout.c_str());
}

INSTANTIATE_TEST_SUITE_P(
    EveryTopology, RealMesh,
    ::testing::Values(
        Case{"mannequin-devil.off", 0, Geometry::Euclidean, Scheme::Yamabe},  // disk, sharp
        Case{"mannequin-devil.off", 0, Geometry::Euclidean, Scheme::InversiveDistance},
        Case{"lion-head.off", 1, Geometry::Euclidean, Scheme::Yamabe},  // disk, 67k
        Case{"elk.off", 0, Geometry::Euclidean, Scheme::Yamabe},        // torus
        Case{"elk.off", 0, Geometry::Euclidean, Scheme::VirtualRadius},
        Case{"femur.off", 0, Geometry::Hyperbolic, Scheme::VirtualRadius},
        Case{"mannequin-devil.off", 0, Geometry::Euclidean, Scheme::Mixed},
        Case{"joint.off", 0, Geometry::Hyperbolic, Scheme::Mixed},
        Case{"rotor_small.off", 0, Geometry::Euclidean, Scheme::InversiveDistance},  // torus
        Case{"femur.off", 0, Geometry::Hyperbolic, Scheme::Yamabe},                  // genus 2
        Case{"joint.off", 0, Geometry::Hyperbolic, Scheme::InversiveDistance},       // genus 2
        Case{"elephant.off", 0, Geometry::Hyperbolic, Scheme::Yamabe},               // genus 3
        Case{"refined_elephant.off", 0, Geometry::Hyperbolic, Scheme::Yamabe},       // genus 3, 89k
        Case{"couplingdown.off", 0, Geometry::Hyperbolic, Scheme::InversiveDistance},  // genus 9
        Case{"blobby.off", 0, Geometry::Spherical, Scheme::Yamabe},                    // genus 0
        Case{"retinal.off", 0, Geometry::Spherical, Scheme::InversiveDistance},        // genus 0
        Case{"bull.off", 0, Geometry::Spherical, Scheme::InversiveDistance},
        Case{"bull.off", 0, Geometry::Spherical, Scheme::VirtualRadius},
        Case{"cow.off", 0, Geometry::Spherical, Scheme::Mixed},
        Case{"cow.off", 0, Geometry::Spherical, Scheme::Tangential}),
    [](const auto& p) {
      std::string n =
          p.param.mesh.substr(0, p.param.mesh.find('.')) + "_" + to_string(p.param.scheme);
      for (char& ch : n) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      }
      return n;
    });

TEST(RealMesh, FixedTriangulationStallsWhereFlipsConverge) {
  const CompactMesh mesh = test::cgal_mesh("mannequin-devil.off");
  SchemeOptions scheme;
  FlowOptions fixed;
  fixed.edge_flips = EdgeFlips::Never;
  const TargetCurvature target = TargetCurvature::free_boundary_or_zero(mesh);
  const FlowResult stalled =
      run_ricci_flow(mesh, prepare_flow(mesh, Geometry::Euclidean, scheme, target), target, fixed);
  EXPECT_FALSE(stalled.converged);
  // By default, flips begin where the fixed triangulation's steps are cut ever shorter to keep
  // its triangles valid, and the flow goes on from there.
  const FlowResult flipped =
      run_ricci_flow(mesh, prepare_flow(mesh, Geometry::Euclidean, scheme, target), target);
  EXPECT_TRUE(flipped.converged);
  ASSERT_GT(flipped.flips_from_iteration, 0);
  EXPECT_NE(flipped.without_flips.find("to keep triangles valid"), std::string::npos)
      << flipped.without_flips;
  EXPECT_EQ(flipped.residual_history.front(), stalled.residual_history.front());
  // The same flow up to there (the residual of the flips' iteration is measured after them).
  EXPECT_EQ(flipped.residual_history[flipped.flips_from_iteration - 1],
            stalled.residual_history[flipped.flips_from_iteration - 1]);
}

// elk.off (a torus scan) calls for flips after 3 iterations on its own triangulation; by default
// the flow then starts again from where Newton began, with flips, and from there it is the flow
// with flips always, iteration for iteration.
TEST(RealMesh, FlipsCalledForEarlyStartWhereNewtonBegan) {
  const CompactMesh mesh = test::cgal_mesh("elk.off");
  const TargetCurvature target = TargetCurvature::free_boundary_or_zero(mesh);
  const ConformalStructure structure =
      prepare_flow(mesh, Geometry::Euclidean, SchemeOptions(), target);
  FlowOptions always;
  always.edge_flips = EdgeFlips::Always;
  const FlowResult flipped = run_ricci_flow(mesh, structure, target, always);
  const FlowResult when_needed = run_ricci_flow(mesh, structure, target);
  ASSERT_TRUE(flipped.converged) << flipped.failure;
  ASSERT_TRUE(when_needed.converged) << when_needed.failure;
  ASSERT_GT(when_needed.flips_from_iteration, 0);
  ASSERT_LE(when_needed.flips_from_iteration, 3);
  EXPECT_EQ(when_needed.iterations, when_needed.flips_from_iteration + flipped.iterations);
  EXPECT_EQ(when_needed.num_flips, flipped.num_flips);
  EXPECT_LE((when_needed.u - flipped.u).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(RealMesh, StereographicStartForTheSphericalFlow) {
  // The lift of the flattened punctured mesh starts the S2 flow near the round sphere.
  SchemeOptions scheme;
  FlowOptions direct;
  direct.stereographic_start = false;
  const CompactMesh blobby = test::cgal_mesh("blobby.off");
  const TargetCurvature zero = TargetCurvature::zero(blobby);
  const FlowResult lifted = compute_ricci_flow(blobby, Geometry::Spherical, scheme, zero);
  const FlowResult plain = compute_ricci_flow(blobby, Geometry::Spherical, scheme, zero, direct);
  EXPECT_LE(lifted.iterations, 5);
  EXPECT_GT(plain.iterations, lifted.iterations);
  EXPECT_LE((lifted.curvature - plain.curvature).cwiseAbs().maxCoeff(), 1e-9);
  // cow.off: the direct flow does not converge; from the (partly reached) lift it does.
  const CompactMesh cow = test::cgal_mesh("cow.off");
  const TargetCurvature cow_zero = TargetCurvature::zero(cow);
  EXPECT_TRUE(compute_ricci_flow(cow, Geometry::Spherical, scheme, cow_zero).converged);
  const ConformalStructure s = prepare_flow(cow, Geometry::Spherical, scheme, cow_zero);
  EXPECT_FALSE(run_ricci_flow(cow, s, cow_zero, direct).converged);
  // bull.off: the highest-degree puncture does not flatten; a later candidate does.
  const CompactMesh bull = test::cgal_mesh("bull.off");
  const FlowResult b =
      compute_ricci_flow(bull, Geometry::Spherical, scheme, TargetCurvature::zero(bull));
  EXPECT_TRUE(b.converged);
  EXPECT_NEAR(b.area, 4 * kPi, 1e-8);
  // The circle packing schemes too: inversive distance on cow.off fails from its own u0.
  scheme.scheme = Scheme::InversiveDistance;
  const ConformalStructure packing = prepare_flow(cow, Geometry::Spherical, scheme, cow_zero);
  EXPECT_TRUE(run_ricci_flow(cow, packing, cow_zero).converged);
  EXPECT_FALSE(run_ricci_flow(cow, packing, cow_zero, direct).converged);
}

}  // namespace
}  // namespace ricci
