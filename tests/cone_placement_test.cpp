// Cone placement on the linear model: Gauss-Bonnet, the angle floor and the bound hold; the model
// is the flow's first order (its error shrinks quadratically with the curvature); budgets and
// quarter angles do what they say.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "flow/linear_cone_model.h"
#include "ricci/flow/cone_placement.h"
#include "ricci/flow/ricci_flow.h"
#include "ricci/mesh/errors.h"
#include "test_meshes.h"

namespace ricci::test {
namespace {

double curvature_sum(const ConePlacement& p) {
  double sum = 0;
  for (const Cone& c : p.cones) sum += 2 * kPi - c.angle;
  return sum;
}

TEST(ConePlacement, ClosedSurfaceConesSatisfyGaussBonnetTheFloorAndTheBound) {
  for (const CompactMesh& mesh : {ellipsoid(3, 1, 1, 2.5), cgal_mesh("eight.off")}) {
    SCOPED_TRACE(mesh.topology_name());
    const ConePlacement p = place_cones(mesh);
    ASSERT_TRUE(p.bound_reached) << p.why_not;
    EXPECT_LE(p.distortion, 0.2);
    EXPECT_NEAR(area_distortion(mesh, p.u), p.distortion, 1e-12);
    EXPECT_NEAR(curvature_sum(p), 2 * kPi * mesh.euler_characteristic(), 1e-8);
    for (const Cone& c : p.cones) {
      EXPECT_GE(c.angle, kPi / 4);
      EXPECT_FALSE(mesh.is_boundary_vertex(c.vertex));
      EXPECT_EQ(p.u[c.vertex], 0);
    }
    EXPECT_EQ(p.factorizations, 1);
    EXPECT_GT(p.back_solves, static_cast<int>(p.cones.size()));
  }
}

TEST(ConePlacement, ManyConesPlacedByHeldSystemStepsAreThoseAFreshFactorizationGives) {
  // From 16 cones the search solves each set it tries from the current set's inverse. The cones it
  // delivers, factored afresh on a model of their own, give its angles, u and D.
  const CompactMesh mesh = cgal_mesh("eight.off");
  ConePlacementOptions o;
  o.distortion_bound = 0.08;  // 40-odd cones on this genus-2 surface
  const ConePlacement p = place_cones(mesh, o);
  ASSERT_TRUE(p.bound_reached) << p.why_not;
  ASSERT_GT(p.cones.size(), 24u);
  LinearConeModel fresh(mesh, LinearSolverKind::Cholmod);
  std::vector<int> cones;
  for (const Cone& c : p.cones) cones.push_back(c.vertex);
  const LinearConeModel::Solution s = fresh.held(cones);
  ASSERT_TRUE(s.ok);
  for (size_t j = 0; j < cones.size(); ++j) {
    EXPECT_NEAR(p.cones[j].angle, 2 * kPi - s.k[static_cast<long>(j)], 1e-9);
  }
  EXPECT_LT((fresh.u(cones, s) - p.u).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(p.distortion, s.d, 1e-9);
  EXPECT_LE(p.distortion, 0.08);
}

// With u solved for from a few cones on (as on a large mesh) the sweeps solve the u without each
// cone for several cones at once, dropped when a cone moves: the placement is the one that sums
// u from the columns, move for move.
TEST(ConePlacement, USolvedAheadInTheSweepsPlacesTheSameCones) {
  const CompactMesh mesh = cgal_mesh("eight.off");
  ConePlacementOptions o;
  o.distortion_bound = 0.08;
  const ConePlacement summed = place_cones(mesh, o);
  o.u_solved_from = 4;
  const ConePlacement solved = place_cones(mesh, o);
  ASSERT_TRUE(summed.bound_reached && solved.bound_reached);
  EXPECT_GT(summed.relocations, 0);  // the sweeps moved cones: blocks were dropped
  EXPECT_EQ(solved.relocations, summed.relocations);
  EXPECT_GT(solved.back_solves, summed.back_solves);  // u solved for
  ASSERT_EQ(solved.cones.size(), summed.cones.size());
  for (size_t j = 0; j < summed.cones.size(); ++j) {
    EXPECT_EQ(solved.cones[j].vertex, summed.cones[j].vertex) << j;
    EXPECT_NEAR(solved.cones[j].angle, summed.cones[j].angle, 1e-9) << j;
  }
  EXPECT_NEAR(solved.distortion, summed.distortion, 1e-9);
  o.u_solved_from = -1;
  EXPECT_THROW(place_cones(mesh, o), InvalidArgumentError);
}

// The bumpy disk with its bump scaled by `height`, as a mesh.
CompactMesh bump(double height) {
  const CompactMesh disk = bumpy_disk(20);
  std::vector<Eigen::Vector3d> p = disk.positions();
  for (auto& q : p) q.z() *= height;
  return CompactMesh(p, disk.faces());
}

TEST(ConePlacement, TheLinearModelIsTheFlowsFirstOrder) {
  // Without cones (the bound met at once), u = 0 on the boundary: the linear model's u against the
  // flow's exact one. Their difference is second order in the curvature: halving the bump's
  // height quarters the difference relative to u, roughly.
  double previous = 0;
  for (double height : {0.8, 0.4, 0.2}) {
    const CompactMesh mesh = bump(height);
    ConePlacementOptions o;
    o.distortion_bound = 10;
    const ConePlacement p = place_cones(mesh, o);
    ASSERT_TRUE(p.cones.empty());
    // The model is the linearization in the canonical class (the input's intrinsic Delaunay
    // triangulation's), where a flow with flips from the start runs.
    FlowOptions flips;
    flips.edge_flips = EdgeFlips::Always;
    const FlowResult flow = compute_ricci_flow(mesh, Geometry::Euclidean, SchemeOptions(),
                                               TargetCurvature::free_boundary(mesh), flips);
    const double relative =
        (flow.u - p.u).lpNorm<Eigen::Infinity>() / flow.u.lpNorm<Eigen::Infinity>();
    if (previous > 0) {
      EXPECT_LT(relative, 0.6 * previous) << "height " << height;
    }
    previous = relative;
  }
  EXPECT_LT(previous, 0.05);
}

TEST(ConePlacement, AFlatEnoughDiskNeedsNoCones) {
  const CompactMesh mesh = bump(0.2);
  const ConePlacement p = place_cones(mesh);
  EXPECT_TRUE(p.cones.empty());
  EXPECT_TRUE(p.bound_reached);
  EXPECT_NEAR(p.distortion, p.distortion_without_cones, 1e-12);
}

TEST(ConePlacement, TheDistortionWithoutConesExistsOnlyWhereAFlatMetricWithoutThemDoes) {
  EXPECT_TRUE(std::isfinite(place_cones(torus(24, 12)).distortion_without_cones));
  EXPECT_TRUE(std::isnan(place_cones(ellipsoid(2)).distortion_without_cones));
}

TEST(ConePlacement, ABudgetStopsThePlacementAndSaysSo) {
  ConePlacementOptions o;
  o.max_cones = 3;
  const ConePlacement p = place_cones(ellipsoid(3, 1, 1, 4), o);
  EXPECT_LE(p.cones.size(), 3u);
  EXPECT_FALSE(p.bound_reached);
  EXPECT_NE(p.why_not.find("budget"), std::string::npos) << p.why_not;
}

// Where the budget stops the placement above the bound, the cones' curvatures are those of least
// D: below the held model's (u = 0 at the cones) at the same cones, no small change of them that
// keeps the constraints lowers it further (curvature moved between two cones; on a surface with
// boundary, one cone's alone), and the floors, Gauss-Bonnet (closed) and the held u's range hold.
void expect_least_distortion_at_eight_cones(const CompactMesh& mesh) {
  ConePlacementOptions o;
  o.max_cones = 8;
  const ConePlacement p = place_cones(mesh, o);
  ASSERT_EQ(p.cones.size(), 8u);
  EXPECT_TRUE(p.least_distortion);
  o.least_distortion_angles = false;
  const ConePlacement held = place_cones(mesh, o);
  EXPECT_FALSE(held.least_distortion);
  ASSERT_FALSE(held.bound_reached);
  LinearConeModel model(mesh, LinearSolverKind::Cholmod);
  std::vector<int> cones;
  for (size_t j = 0; j < p.cones.size(); ++j) {
    cones.push_back(p.cones[j].vertex);
    EXPECT_EQ(held.cones[j].vertex, p.cones[j].vertex);
  }
  const LinearConeModel::Solution s = model.held(cones);
  ASSERT_TRUE(s.ok);
  EXPECT_NEAR(held.distortion, s.d, 1e-9);
  EXPECT_LT(p.distortion, 0.95 * s.d);
  if (mesh.is_closed()) {
    EXPECT_NEAR(curvature_sum(p), 2 * kPi * mesh.euler_characteristic(), 1e-8);
  }
  Eigen::VectorXd k(8);
  for (long j = 0; j < 8; ++j) {
    k[j] = 2 * kPi - p.cones[static_cast<size_t>(j)].angle;
    EXPECT_GE(p.cones[static_cast<size_t>(j)].angle, kPi / 4);
  }
  EXPECT_NEAR(model.distortion(cones, k), p.distortion, 1e-9);
  EXPECT_NEAR(area_distortion(mesh, p.u), p.distortion, 1e-9);
  std::vector<double> widest(mesh.num_vertices(), 0), angle_sum(mesh.num_vertices(), 0);
  for (const auto& t : mesh.faces()) {
    for (int c = 0; c < 3; ++c) {
      const auto& x = mesh.positions();
      const Eigen::Vector3d a = x[t[(c + 1) % 3]] - x[t[c]], b = x[t[(c + 2) % 3]] - x[t[c]];
      const double corner = std::atan2(a.cross(b).norm(), a.dot(b));
      widest[t[c]] = std::max(widest[t[c]], corner);
      angle_sum[t[c]] += corner;
    }
  }
  const Eigen::VectorXd u = model.u(cones, s);
  const double mean = model.area().dot(u), p_mean = model.area().dot(p.u);
  for (int c : cones) {
    EXPECT_LE(p.u[c] - p_mean, u.maxCoeff() - mean + 1e-9);
    EXPECT_GE(p.u[c] - p_mean, u.minCoeff() - mean - 1e-9);
  }
  // The curvature changes: +1e-4 at i and -1e-4 at j (j = -1: none; i = -1 likewise), each
  // tried where it keeps every constraint: D does not fall (to second order it rises).
  int moves = 0;
  for (long i = -1; i < 8; ++i) {
    for (long j = -1; j < 8; ++j) {
      if (i == j || (mesh.is_closed() && (i < 0 || j < 0))) continue;
      Eigen::VectorXd moved = k;
      if (i >= 0) moved[i] += 1e-4;
      if (j >= 0) moved[j] -= 1e-4;
      const Eigen::VectorXd v = model.prescribed(cones, moved);
      const double v_mean = model.area().dot(v);
      bool kept = true;
      for (int c : cones) {
        kept = kept && v[c] - v_mean <= u.maxCoeff() - mean && v[c] - v_mean >= u.minCoeff() - mean;
      }
      // The cone that gains curvature stays within its floor; the one that loses it opens its
      // corners wider and must stay drawable (its widest corner opened at most 0.9 pi), or as
      // the held model's was.
      if (i >= 0) kept = kept && 2 * kPi - moved[i] >= kPi / 4;
      if (j >= 0) {
        const int w = cones[static_cast<size_t>(j)];
        kept = kept && moved[j] >= std::min(s.k[j], 2 * kPi - 0.9 * kPi * angle_sum[w] / widest[w]);
      }
      if (!kept) continue;
      ++moves;
      EXPECT_GE(model.distortion(cones, moved), p.distortion - 1e-12) << i << " to " << j;
    }
  }
  EXPECT_GT(moves, 0);
}

TEST(ConePlacement, AtTheBudgetTheConesCurvaturesAreThoseOfLeastDistortion) {
  for (const char* name : {"bull.off", "pig.off"}) {
    SCOPED_TRACE(name);
    expect_least_distortion_at_eight_cones(cgal_mesh(name));
  }
}

TEST(ConePlacement, NoConeOpensACornerOfItsFacesNearAHalfTurn) {
  // CGAL's bull at 8 cones: the peaks of |u| put two cones of about 12 rad (a little less than two
  // turns) at vertices of five faces, whose corners of 115 and 102 degrees the flat metric opened
  // to 3.7 and 3.9 rad (this estimate: 3.5 and 3.3). Each corner of a cone's faces, in 3D, times
  // the cone's angle over the vertex's angle sum, stays below a half turn.
  const CompactMesh bull = cgal_mesh("bull.off");
  ConePlacementOptions o;
  o.max_cones = 8;
  const ConePlacement p = place_cones(bull, o);
  ASSERT_EQ(p.cones.size(), 8u);
  int wide = 0;
  for (const Cone& c : p.cones) {
    double widest = 0, sum = 0;
    for (const auto& t : bull.faces()) {
      for (int k = 0; k < 3; ++k) {
        if (t[k] != c.vertex) continue;
        const Eigen::Vector3d a = bull.positions()[t[(k + 1) % 3]] - bull.positions()[t[k]];
        const Eigen::Vector3d b = bull.positions()[t[(k + 2) % 3]] - bull.positions()[t[k]];
        const double corner = std::acos(a.normalized().dot(b.normalized()));
        widest = std::max(widest, corner), sum += corner;
      }
    }
    EXPECT_LT(widest * c.angle / sum, kPi) << "cone at " << c.vertex;
    wide += c.angle > 2 * kPi;
  }
  EXPECT_GE(wide, 1);  // the bull's wide cones are there to be placed
}

// The angle sum in 3D at vertex v, and the corners there.
double angle_sum_at(const CompactMesh& mesh, int v) {
  double sum = 0;
  for (const auto& t : mesh.faces()) {
    for (int k = 0; k < 3; ++k) {
      if (t[k] != v) continue;
      const Eigen::Vector3d a = mesh.positions()[t[(k + 1) % 3]] - mesh.positions()[t[k]];
      const Eigen::Vector3d b = mesh.positions()[t[(k + 2) % 3]] - mesh.positions()[t[k]];
      sum += std::acos(a.normalized().dot(b.normalized()));
    }
  }
  return sum;
}

TEST(ConePlacement, ASpikesTipKeepsItsOwnSharpConeAndNoConesCrowdIt) {
  // A sphere with one vertex pulled out to a spike whose tip's angle sum is below the floor. A
  // placement that widened the tip's cone added cones near it until the budget or the vertices ran
  // out (a robot's leg part: 1,024 cones placed in 132 s; 88 in 0.09 s since). The tip may keep a
  // cone of half its own angle sum; every other cone keeps the floor. At a budget of one cone, that
  // cone carries all the curvature, sharper than any floor: said so.
  const CompactMesh sphere = ellipsoid(3);
  std::vector<Eigen::Vector3d> p = sphere.positions();
  p[0] *= 3;
  const CompactMesh spiked(p, sphere.faces());
  const double tip_sum = angle_sum_at(spiked, 0);
  ASSERT_LT(tip_sum, kPi / 4);  // below the floor: the tip's own cone would be too sharp
  const ConePlacement placed = place_cones(spiked);
  ASSERT_TRUE(placed.bound_reached) << placed.why_not;
  EXPECT_LT(placed.cones.size(), 32u);
  bool tip = false;
  for (const Cone& c : placed.cones) {
    if (c.vertex == 0) {
      tip = true;
      EXPECT_LT(c.angle, kPi / 4);
      EXPECT_GE(c.angle, tip_sum / 2);
    } else {
      EXPECT_GE(c.angle, kPi / 4) << "cone at " << c.vertex;
    }
  }
  EXPECT_TRUE(tip);
  ConePlacementOptions one;
  one.max_cones = 1;
  const ConePlacement alone = place_cones(spiked, one);
  ASSERT_EQ(alone.cones.size(), 1u);
  EXPECT_TRUE(alone.sharp_cone);
  EXPECT_FALSE(alone.bound_reached);
  EXPECT_NE(alone.why_not.find("sharper than the floor remains at the budget"), std::string::npos)
      << alone.why_not;
}

TEST(ConePlacement, QuarterAnglesAreQuarterTurnsSummingToGaussBonnet) {
  ConePlacementOptions o;
  o.quarter_angles = true;
  const CompactMesh mesh = ellipsoid(3, 1, 1, 2.5);
  const ConePlacement p = place_cones(mesh, o);
  ASSERT_FALSE(p.cones.empty());
  for (const Cone& c : p.cones) {
    const double quarters = c.angle / (kPi / 2);
    EXPECT_NEAR(quarters, std::round(quarters), 1e-12);
    EXPECT_GE(c.angle, kPi / 2 - 1e-12);
  }
  EXPECT_NEAR(curvature_sum(p), 4 * kPi, 1e-9);
  // Rounding moves D; where it leaves D above the bound, the placement says so.
  EXPECT_NEAR(area_distortion(mesh, p.u), p.distortion, 1e-12);
  EXPECT_EQ(p.bound_reached, p.distortion <= 0.2);
  if (!p.bound_reached) {
    EXPECT_NE(p.why_not.find("quarter"), std::string::npos);
  }
}

TEST(ConePlacement, QuarterTurnsRoundedAwayFromTheBoundAreMovedBackTowardsIt) {
  // CGAL's Homer (closed, genus 0): its cones for D <= 0.2 rounded to quarter turns each left the
  // linear model's D at 0.741 (measured on 2026-12-07, before quarter turns were moved); a
  // quarter turn of curvature moved at a time from where u is highest to where it is lowest brings
  // it to 0.389 (the atlas, with its attempts at tighter bounds, from 0.922 to 0.229). Every cone
  // stays a quarter turn within the floor, their sum Gauss-Bonnet's.
  ConePlacementOptions o;
  o.quarter_angles = true;
  const CompactMesh mesh = test::cgal_mesh("homer.off");
  const ConePlacement p = place_cones(mesh, o);
  for (const Cone& c : p.cones) {
    const double quarters = c.angle / (kPi / 2);
    EXPECT_NEAR(quarters, std::round(quarters), 1e-12);
    EXPECT_GE(c.angle, o.min_cone_angle - 1e-12);
  }
  EXPECT_NEAR(curvature_sum(p), 4 * kPi, 1e-9);
  EXPECT_NEAR(area_distortion(mesh, p.u), p.distortion, 1e-12);
  EXPECT_LT(p.distortion, 0.5) << p.distortion;
}

TEST(ConePlacement, OptionsOutOfRangeAreRefused) {
  ConePlacementOptions o;
  o.distortion_bound = 0;
  EXPECT_THROW(place_cones(ellipsoid(1), o), InvalidArgumentError);
}

}  // namespace
}  // namespace ricci::test
