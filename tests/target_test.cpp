// Targets that admit no solution are refused before any iteration, with the reason.
#include "ricci/flow/target.h"

#include "ricci/flow/presets.h"

#include <cmath>

#include <gtest/gtest.h>

#include "ricci/mesh/errors.h"
#include "test_meshes.h"

namespace ricci {
namespace {

std::string refusal(const CompactMesh& mesh, Geometry g, const TargetCurvature& t) {
  try {
    check_target(mesh, g, t);
  } catch (const InvalidTargetError& e) {
    return e.what();
  }
  return "";
}

TEST(Target, PresetsAndAutomaticGeometry) {
  const CompactMesh disk = test::bumpy_disk(5), torus = test::torus(8, 5),
                    sphere = test::ellipsoid(1);
  const TargetCurvature fb = TargetCurvature::free_boundary(disk);
  for (int v = 0; v < disk.num_vertices(); ++v)
    EXPECT_EQ(fb.is_fixed(v), disk.is_boundary_vertex(v));
  EXPECT_EQ(TargetCurvature::free_boundary_or_zero(torus).num_fixed(), 0);
  EXPECT_EQ(automatic_preset(disk).second, Geometry::Euclidean);
  EXPECT_EQ(automatic_preset(torus).second, Geometry::Euclidean);
  EXPECT_EQ(automatic_preset(sphere).second, Geometry::Spherical);
  EXPECT_EQ(automatic_preset(test::cgal_mesh("eight.off")).second, Geometry::Hyperbolic);
}

TEST(Target, AcceptsTheUniformizationTargets) {
  EXPECT_EQ(
      refusal(test::torus(8, 5), Geometry::Euclidean, TargetCurvature::zero(test::torus(8, 5))),
      "");
  const CompactMesh sphere = test::ellipsoid(1), eight = test::cgal_mesh("eight.off");
  EXPECT_EQ(refusal(sphere, Geometry::Spherical, TargetCurvature::zero(sphere)), "");
  EXPECT_EQ(refusal(eight, Geometry::Hyperbolic, TargetCurvature::zero(eight)), "");
  EXPECT_NEAR(gauss_bonnet_area(sphere, Geometry::Spherical, TargetCurvature::zero(sphere)),
              4 * kPi, 1e-12);
  EXPECT_NEAR(gauss_bonnet_area(eight, Geometry::Hyperbolic, TargetCurvature::zero(eight)), 4 * kPi,
              1e-12);
}

TEST(Target, RefusesGaussBonnetViolations) {
  const CompactMesh torus = test::torus(8, 5), sphere = test::ellipsoid(1);
  std::string m = refusal(torus, Geometry::Spherical, TargetCurvature::zero(torus));
  EXPECT_NE(m.find("spherical geometry needs sum Kbar < 2 pi chi"), std::string::npos) << m;
  EXPECT_NE(m.find("use euclidean"), std::string::npos) << m;
  m = refusal(sphere, Geometry::Hyperbolic, TargetCurvature::zero(sphere));
  EXPECT_NE(m.find("hyperbolic geometry needs"), std::string::npos) << m;
  m = refusal(sphere, Geometry::Euclidean, TargetCurvature::zero(sphere));
  EXPECT_NE(m.find("Gauss-Bonnet fails"), std::string::npos) << m;
  EXPECT_NE(m.find("use spherical geometry"), std::string::npos) << m;
  // A disk with every curvature prescribed: the values must sum to 2 pi.
  const CompactMesh disk = test::bumpy_disk(5);
  m = refusal(disk, Geometry::Euclidean, TargetCurvature::zero(disk));
  EXPECT_NE(m.find("2 pi chi = 6.28"), std::string::npos) << m;
}

TEST(Target, RefusesCurvatureAtOrAboveTwoPi) {
  const CompactMesh torus = test::torus(8, 5);
  TargetCurvature t = TargetCurvature::zero(torus);
  t.curvature[3] = 2 * kPi;
  t.curvature[4] = -2 * kPi;
  const std::string m = refusal(torus, Geometry::Euclidean, t);
  EXPECT_NE(m.find("vertex 3"), std::string::npos) << m;
  EXPECT_NE(m.find("Kbar < 2 pi"), std::string::npos) << m;
}

TEST(Target, FromValuesTreatsNanAsFixed) {
  const CompactMesh disk = test::bumpy_disk(3);
  Eigen::VectorXd values = Eigen::VectorXd::Zero(disk.num_vertices());
  values[0] = std::nan("");
  const TargetCurvature t = TargetCurvature::from_values(disk, values);
  EXPECT_TRUE(t.is_fixed(0));
  EXPECT_EQ(t.num_fixed(), 1);
  EXPECT_THROW(TargetCurvature::from_values(disk, Eigen::VectorXd::Zero(3)), InvalidTargetError);
}

}  // namespace
}  // namespace ricci
