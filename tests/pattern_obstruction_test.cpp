// Thurston's condition at a vertex: the angle sum of a circle meeting its neighbours at angles
// Phi stays below sum (pi - Phi) over its link edges, so a degree-3 vertex needs Phi < 60 deg.
#include <cmath>

#include <gtest/gtest.h>

#include "flow/pattern_obstruction.h"
#include "ricci/flow/ricci_flow.h"
#include "test_meshes.h"

namespace ricci {
namespace {

constexpr double kDegree = kPi / 180;

CompactMesh tetrahedron() {
  return CompactMesh({{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}},
                     {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}});
}

ConformalStructure thurston(const CompactMesh& mesh, Geometry g, double degrees) {
  SchemeOptions options;
  options.scheme = Scheme::Thurston;
  options.intersection_angle = degrees * kDegree;
  return prepare_flow(mesh, g, options, TargetCurvature::zero(mesh));
}

TEST(PatternObstruction, DegreeThreeVertexNeedsAnglesBelowSixtyDegrees) {
  const CompactMesh mesh = tetrahedron();
  const TargetCurvature zero = TargetCurvature::zero(mesh);
  const std::string at_60 =
      circle_pattern_obstruction(mesh, thurston(mesh, Geometry::Spherical, 60), zero);
  EXPECT_NE(at_60.find("vertex 0 (degree 3)"), std::string::npos) << at_60;
  EXPECT_NE(at_60.find("4 vertices fail it"), std::string::npos) << at_60;
  EXPECT_NE(at_60.find("Thurston's condition"), std::string::npos) << at_60;
  EXPECT_NE(circle_pattern_obstruction(mesh, thurston(mesh, Geometry::Spherical, 75), zero), "");
  EXPECT_EQ(circle_pattern_obstruction(mesh, thurston(mesh, Geometry::Spherical, 59), zero), "");
}

TEST(PatternObstruction, TargetCurvatureMovesTheBound) {
  // A cone of curvature 30 deg at vertex 0 asks for 330 deg: reachable at Phi = 65 deg
  // (3 x 115 = 345 deg), not at Phi = 70 deg (330 deg, the limit itself).
  const CompactMesh mesh = tetrahedron();
  Eigen::VectorXd kbar = Eigen::VectorXd::Constant(4, std::nan(""));
  kbar[0] = 30 * kDegree;
  const TargetCurvature cone = TargetCurvature::from_values(mesh, kbar);
  EXPECT_EQ(circle_pattern_obstruction(mesh, thurston(mesh, Geometry::Spherical, 65), cone), "");
  EXPECT_NE(circle_pattern_obstruction(mesh, thurston(mesh, Geometry::Spherical, 70), cone), "");
}

TEST(PatternObstruction, OtherSchemesAreNotChecked) {
  const CompactMesh mesh = tetrahedron();
  const TargetCurvature zero = TargetCurvature::zero(mesh);
  for (Scheme s : {Scheme::Tangential, Scheme::Yamabe, Scheme::VirtualRadius}) {
    SchemeOptions options;
    options.scheme = s;
    EXPECT_EQ(circle_pattern_obstruction(
                  mesh, prepare_flow(mesh, Geometry::Spherical, options, zero), zero),
              "")
        << to_string(s);
  }
}

TEST(PatternObstruction, FlowReportsItInsteadOfADegeneratePattern) {
  // cow.off has 21 degree-3 vertices. At 60 deg Newton used to "converge" with their radii at
  // 1e-16 of the median; now the flow says why there is no solution. At 50 deg it converges to a
  // pattern whose smallest circle is 2.8e-4 of the median (degree-3 vertices have small circles).
  const CompactMesh cow = test::cgal_mesh("cow.off");
  const TargetCurvature zero = TargetCurvature::zero(cow);
  const FlowResult at_60 = run_ricci_flow(cow, thurston(cow, Geometry::Spherical, 60), zero);
  EXPECT_FALSE(at_60.converged);
  EXPECT_NE(at_60.failure.find("21 vertices fail it"), std::string::npos) << at_60.failure;
  const FlowResult at_50 = run_ricci_flow(cow, thurston(cow, Geometry::Spherical, 50), zero);
  ASSERT_TRUE(at_50.converged) << at_50.failure;
  Eigen::VectorXd radius = at_50.radius;
  std::sort(radius.data(), radius.data() + radius.size());
  EXPECT_GT(radius[0], 1e-5 * radius[radius.size() / 2]);  // measured: 2.8e-4
}

}  // namespace
}  // namespace ricci
