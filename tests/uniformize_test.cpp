// Target presets and the uniformization pipeline: the unit disk against the analytic conformal map
// of a square, circle domains, polygons from corner angles, automatic choices by topology, and the
// errors of requests that cannot be met.
#include "ricci/uniformize.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ricci/atlas.h"
#include "ricci/errors.h"
#include "ricci/mesh_io.h"
#include "test_meshes.h"

namespace ricci {
namespace {

using Complex = std::complex<double>;

// A mesh of the real-mesh set (meshes/real-meshes.tsv: origins and licences), as repaired.
RepairedMesh real_mesh(const std::string& name) {
  const MeshFile file = read_mesh_file(std::string(RICCI_REAL_MESH_DIR) + "/" + name);
  return repair_mesh(file.positions, file.triangles);
}

// Faces of a planar layout (the plane or the Poincare disk, z = 0) not counter-clockwise, counted
// here rather than by the code under test. Forgiven: an orientation within what the corners'
// rounding decides is not counted (such faces are collapsed, and warned of); Counted: any
// orientation that is not positive is.
enum class Rounding { Forgiven, Counted };
int turned_in_plane(const std::vector<std::array<Eigen::Vector3d, 3>>& corners, Rounding rounding) {
  int turned = 0;
  for (const auto& t : corners) {
    const Eigen::Vector3d a = t[1] - t[0], b = t[2] - t[0];
    const double cross = a.x() * b.y() - a.y() * b.x();
    const double size = std::max({t[0].norm(), t[1].norm(), t[2].norm()});
    const double noise = 64 * 2.220446049250313e-16 * size * (a.norm() + b.norm());
    turned += rounding == Rounding::Forgiven ? cross < -noise : !(cross > 0);
  }
  return turned;
}

// The Schwarz-Christoffel map of the unit disk onto the square [-1, 1]^2 (corners at w^4 = -1):
// f(w) = c * integral_0^w dt / sqrt(1 + t^4), along the ray after s = 1 - (1 - sigma)^2, which
// smooths the corners' square-root singularity; two-point Gauss-Legendre on 400 panels.
Complex ray_integral(Complex w) {
  const int panels = 400;
  const double node = 0.5 / std::sqrt(3.0);
  Complex sum = 0;
  for (int k = 0; k < panels; ++k) {
    for (double offset : {0.5 - node, 0.5 + node}) {
      const double sigma = (k + offset) / panels, s = 1 - (1 - sigma) * (1 - sigma);
      const Complex t = s * w;
      sum += w * 2.0 * (1 - sigma) / std::sqrt(1.0 + t * t * t * t);
    }
  }
  return sum / (2.0 * panels);
}

Complex square_map(Complex w) {
  static const double c = std::sqrt(2.0) / std::abs(ray_integral(std::polar(1.0, kPi / 4)));
  return c * ray_integral(w);
}

// The inverse map at z, by Newton's method from w (the computed image).
Complex inverse_square_map(Complex z, Complex w) {
  static const double c = std::sqrt(2.0) / std::abs(ray_integral(std::polar(1.0, kPi / 4)));
  for (int it = 0; it < 50; ++it) {
    const Complex step = (square_map(w) - z) * std::sqrt(1.0 + w * w * w * w) / c;
    w -= step;
    if (std::abs(step) < 1e-14) break;
  }
  return w;
}

struct SquareError {
  double max = 0, mean = 0, corner = 0;
};

// The disk preset on an n x n grid of [-1, 1]^2, centre vertex at 0 and the right side's midpoint
// on the positive axis, against the analytic map.
SquareError square_to_disk_error(int n) {
  const CompactMesh grid = test::square_grid(n);
  UniformizationOptions o;
  o.preset = TargetPreset::UnitDisk;
  o.center_vertex = (n / 2) * (n + 1) + n / 2;
  o.axis_vertex = (n / 2) * (n + 1) + n;
  const Uniformization u = uniformize(grid, o);
  EXPECT_TRUE(u.result.converged) << u.result.failure;
  EXPECT_EQ(u.layout_kind, LayoutKind::Plane);
  SquareError e;
  int count = 0;
  for (int v = 0; v < grid.num_vertices(); ++v) {
    const Complex z(2 * grid.positions()[v].x() - 1, 2 * grid.positions()[v].y() - 1);
    const Complex w(u.position[v].x(), u.position[v].y());
    if (std::abs(std::abs(z.real()) - 1) < 1e-12 && std::abs(std::abs(z.imag()) - 1) < 1e-12) {
      e.corner = std::max(e.corner, std::abs(w - std::polar(1.0, std::arg(z))));
      continue;  // the map's derivative is infinite at the corners
    }
    const double d = std::abs(inverse_square_map(z, w) - w);
    e.max = std::max(e.max, d);
    e.mean += d;
    ++count;
  }
  e.mean /= count;
  return e;
}

TEST(Uniformize, SquareOntoTheDiskConvergesToTheConformalMap) {
  // The analytic map itself: corners on the diagonals, the axis point fixed.
  EXPECT_NEAR(std::abs(square_map(std::polar(1.0, kPi / 4)) - Complex(1, 1)), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(square_map(1.0) - 1.0), 0.0, 1e-12);
  const SquareError e8 = square_to_disk_error(8), e16 = square_to_disk_error(16),
                    e32 = square_to_disk_error(32);
  std::printf(
      "square -> disk, max/mean/corner error: n=8 %.2e/%.2e/%.2e  n=16 %.2e/%.2e/%.2e  "
      "n=32 %.2e/%.2e/%.2e\n",
      e8.max, e8.mean, e8.corner, e16.max, e16.mean, e16.corner, e32.max, e32.mean, e32.corner);
  EXPECT_LT(e16.max, e8.max);
  EXPECT_LT(e32.max, e16.max);
  EXPECT_LT(e16.mean, 0.6 * e8.mean);
  EXPECT_LT(e32.mean, 0.6 * e16.mean);
  EXPECT_LT(e32.max, 0.02);
  EXPECT_LT(e32.corner, 0.02);
}

TEST(Uniformize, EdgeFlipsOnlyWhereTheFlowStalls) {
  // hand.off: the round sphere's Yamabe flow cannot walk to its stereographic start on the input's
  // triangulation, and Newton gets stuck there or creeps; by default the walk is made again with
  // flips, and the report says from which iteration and why.
  const CompactMesh hand = test::cgal_mesh("hand.off");
  UniformizationOptions o;
  const Uniformization run = uniformize(hand, o);
  ASSERT_TRUE(run.valid()) << run.result.failure << run.layout_failure;
  ASSERT_GT(run.totals.flips_from_iteration, 0);
  // Newton stalls, or its steps are cut ever shorter, on the input's triangulation.
  const std::string& why = run.totals.without_flips;
  EXPECT_TRUE(why.find("no step of length") != std::string::npos ||
              why.find("to keep triangles valid") != std::string::npos)
      << why;
  EXPECT_LE(run.totals.newton_iterations - run.totals.flips_from_iteration, 10);
  EXPECT_GT(run.totals.edge_flips, 0);
  const Uniformization sphere = uniformize(test::ellipsoid(2, 1, 1, 2), o);
  EXPECT_TRUE(sphere.valid());
  EXPECT_EQ(sphere.totals.flips_from_iteration, -1);
  EXPECT_EQ(sphere.totals.edge_flips, 0);
  int calls = 0;
  o.flow.progress = [&](const FlowProgress&) {
    ++calls;
    return false;  // cancel at once
  };
  const Uniformization cancelled = uniformize(hand, o);
  EXPECT_FALSE(cancelled.converged());
  EXPECT_EQ(cancelled.result.stop, FlowStop::Cancelled);
  EXPECT_EQ(calls, 1);
}

// The unit disk by default: on the input's triangulation wherever the one solve or, after it, the
// repeated flows get there without flips (the same u as --flips never); else as with flips always.
// Real meshes from the real-mesh set (meshes/real-meshes.tsv): OpenFOAM's mixer vessel, whose one
// solve stops at its first step but whose repeated flows converge on it, and meshcat's slotted
// disk (a sphere with 3 holes), which needs flips.
TEST(Uniformize, UnitDiskFlipsOnlyWhereNoFlowOnTheInputReachesIt) {
  const auto run = [](const std::string& name, EdgeFlips flips) {
    const RepairedMesh repaired = real_mesh(name);
    EXPECT_EQ(repaired.components.size(), 1u);
    UniformizationOptions o;
    o.flow.edge_flips = flips;
    return uniformize(repaired.components[0].mesh, o);
  };
  const auto max_difference = [](const Uniformization& a, const Uniformization& b) {
    return (a.result.u - b.result.u).cwiseAbs().maxCoeff();
  };
  const Uniformization vessel = run("openfoam-mixer-vessel.stl", EdgeFlips::WhenNeeded);
  const Uniformization vessel_never = run("openfoam-mixer-vessel.stl", EdgeFlips::Never);
  ASSERT_TRUE(vessel_never.valid()) << vessel_never.result.failure << vessel_never.layout_failure;
  ASSERT_TRUE(vessel.valid()) << vessel.result.failure << vessel.layout_failure;
  EXPECT_EQ(vessel.preset, TargetPreset::UnitDisk);
  EXPECT_GT(vessel.totals.flows, 1);  // the one solve, then the repeated flows
  EXPECT_EQ(vessel.totals.edge_flips, 0);
  EXPECT_EQ(vessel.totals.flips_from_iteration, -1);
  EXPECT_LE(max_difference(vessel, vessel_never), 1e-9);

  const Uniformization slotted = run("meshcat-slotted-disk.stl", EdgeFlips::WhenNeeded);
  const Uniformization slotted_always = run("meshcat-slotted-disk.stl", EdgeFlips::Always);
  EXPECT_FALSE(run("meshcat-slotted-disk.stl", EdgeFlips::Never).converged());
  ASSERT_TRUE(slotted_always.valid()) << slotted_always.result.failure;
  ASSERT_TRUE(slotted.valid()) << slotted.result.failure << slotted.layout_failure;
  EXPECT_GT(slotted.totals.edge_flips, 0);
  EXPECT_GT(slotted.totals.flips_from_iteration, 0);
  EXPECT_NE(slotted.totals.without_flips.find("the one solve: "), std::string::npos);
  EXPECT_NE(slotted.totals.without_flips.find("the repeated flows: "), std::string::npos);
  EXPECT_LE(max_difference(slotted, slotted_always), 1e-9);
}

// PyVista's airplane (component 0, a genus-0 surface with 2 boundary loops, from the real-mesh
// set): its circle domain squeezes 300 faces far down the fuselage below double precision, and its
// loops come off their circles. The automatic target then gives the free boundary's map, and says
// why; asked for explicitly, the circle domain is refused.
TEST(Uniformize, AutomaticTargetKeepsTheBoundaryWhereCirclesAreBelowPrecision) {
  const RepairedMesh repaired = real_mesh("pyvista-airplane.ply");
  ASSERT_GT(repaired.components.size(), 1u);
  const CompactMesh& mesh = repaired.components[0].mesh;
  ASSERT_EQ(mesh.num_boundary_loops(), 2);
  UniformizationOptions disk;
  disk.preset = TargetPreset::UnitDisk;
  const Uniformization circles = uniformize(mesh, disk);
  ASSERT_TRUE(circles.converged()) << circles.result.failure;
  EXPECT_FALSE(circles.valid());
  EXPECT_GT(circles.quality.collapsed_faces, 0);
  EXPECT_TRUE(circles.target_instead.empty());

  const Uniformization automatic = uniformize(mesh, UniformizationOptions());
  ASSERT_TRUE(automatic.valid()) << automatic.result.failure << automatic.layout_failure;
  EXPECT_EQ(automatic.preset, TargetPreset::FreeBoundary);
  EXPECT_NE(automatic.target_instead.find("squeezes"), std::string::npos)
      << automatic.target_instead;
  EXPECT_EQ(automatic.quality.flipped_faces, 0);
  EXPECT_EQ(automatic.quality.collapsed_faces, 0);
  EXPECT_LE(automatic.quality.max_curvature_error, 1e-9);
  // The report counts the circle domain's flows too.
  EXPECT_EQ(automatic.totals.flows, circles.totals.flows + 1);
  // Edge flips are the delivered flow's, not the circle domain's.
  EXPECT_EQ(automatic.totals.edge_flips, automatic.result.num_flips);
  EXPECT_EQ(automatic.totals.newton_iterations,
            circles.totals.newton_iterations + automatic.result.iterations);
}

// OpenCASCADE's video part (a genus-0 surface with 12 boundary loops, from the real-mesh set): the
// one solve stalls even with flips, and the repeated flows' boundary curvature goes up and down
// between 1e-3 and 1e-2 instead of settling. The fit gives up once it has not changed less for 40
// flows, not after 200, and the automatic target gives the free boundary's map, saying why.
TEST(Uniformize, AutomaticTargetKeepsTheBoundaryWhereCirclesDoNotSettle) {
  const RepairedMesh repaired = real_mesh("occt-video-part.stl");
  ASSERT_EQ(repaired.components.size(), 1u);
  const CompactMesh& mesh = repaired.components[0].mesh;
  ASSERT_EQ(mesh.num_boundary_loops(), 12);
  const Uniformization run = uniformize(mesh, UniformizationOptions());
  ASSERT_TRUE(run.valid()) << run.result.failure << run.layout_failure;
  EXPECT_EQ(run.preset, TargetPreset::FreeBoundary);
  EXPECT_NE(run.target_instead.find("the circle domain was not reached"), std::string::npos)
      << run.target_instead;
  EXPECT_NE(run.target_instead.find("no longer settles"), std::string::npos) << run.target_instead;
  EXPECT_LT(run.totals.flows, 150);
  EXPECT_EQ(run.quality.flipped_faces, 0);
}

TEST(Uniformize, DiskPresetPutsTheBoundaryOnTheUnitCircle) {
  const CompactMesh disk = test::cgal_mesh("nefertiti.off");
  UniformizationOptions o;  // auto: a disk goes to the unit disk
  int interior = 0;
  while (disk.is_boundary_vertex(interior)) ++interior;
  o.center_vertex = interior;
  o.axis_vertex = disk.boundary_loops()[0][0];
  o.preset = TargetPreset::FreeBoundary;
  EXPECT_THROW(uniformize(disk, o), InvalidArgumentError);  // a centre needs the disk preset
  o.preset = TargetPreset::Automatic;                       // a disk's automatic preset
  const Uniformization u = uniformize(disk, o);
  ASSERT_TRUE(u.result.converged) << u.result.failure;
  EXPECT_LE(u.circle_error, 1e-8);
  for (int v : disk.boundary_loops()[0]) EXPECT_NEAR(u.position[v].norm(), 1.0, 1e-8);
  EXPECT_LE(u.position[interior].norm(), 1e-12);
  EXPECT_NEAR(u.position[o.axis_vertex].x(), 1.0, 1e-8);
  EXPECT_NEAR(u.position[o.axis_vertex].y(), 0.0, 1e-12);
  EXPECT_EQ(u.quality.flipped_faces, 0);
  EXPECT_LE(u.quality.max_curvature_error, 1e-9);
  EXPECT_LT(u.totals.flows, 40);
}

TEST(Uniformize, GenusZeroWithSevenHolesBecomesACircleDomain) {
  const CompactMesh holes = test::cgal_mesh("holes.off");
  ASSERT_EQ(holes.num_boundary_loops(), 7);
  const Uniformization u = uniformize(holes, {});
  ASSERT_TRUE(u.result.converged) << u.result.failure;
  EXPECT_EQ(u.preset, TargetPreset::UnitDisk);
  EXPECT_EQ(u.geometry, Geometry::Euclidean);
  EXPECT_EQ(u.layout_kind, LayoutKind::Plane);
  EXPECT_LE(u.circle_error, 1e-7);  // every loop on a circle
  // The cut closes up: the deck transformations are the identity, so the domain is planar.
  EXPECT_LE(u.layout.closure_error, 1e-9);
  for (const DiskIsometry& d : u.layout.deck) {
    EXPECT_LE(std::abs(d.a - 1.0), 1e-7);
    EXPECT_LE(std::abs(d.b), 1e-7);
  }
  // The outer loop is the unit circle and the others lie inside it.
  const int outer = outer_boundary_loop(holes, holes.input_lengths());
  for (int c = 0; c < holes.num_boundary_loops(); ++c) {
    for (int v : holes.boundary_loops()[c]) {
      if (c == outer) {
        EXPECT_NEAR(u.position[v].norm(), 1.0, 1e-7);
      } else {
        EXPECT_LT(u.position[v].norm(), 1.0 - 1e-3);
      }
    }
  }
  EXPECT_EQ(u.quality.flipped_faces, 0);
}

TEST(Uniformize, CornerAnglesMakeARectangle) {
  const CompactMesh disk = test::cgal_mesh("nefertiti.off");
  const std::vector<int>& loop = disk.boundary_loops()[0];
  const size_t n = loop.size();
  std::vector<Cone> corners;
  for (size_t k = 0; k < 4; ++k) corners.push_back({loop[k * n / 4], kPi / 2});
  UniformizationOptions o;
  o.preset = TargetPreset::Values;
  o.values = cone_target(disk, corners).curvature;
  const Uniformization u = uniformize(disk, o);
  ASSERT_TRUE(u.result.converged) << u.result.failure;
  EXPECT_EQ(u.geometry, Geometry::Euclidean);  // four right angles: Gauss-Bonnet in E2
  // Every boundary vertex lies on the side through the two corners around it, and the sides meet
  // at right angles.
  double size = 0;
  for (const auto& p : u.position) size = std::max(size, p.norm());
  for (size_t k = 0; k < 4; ++k) {
    const size_t begin = k * n / 4, end = (k + 1) * n / 4;
    const Eigen::Vector2d a = u.position[loop[begin]].head<2>();
    const Eigen::Vector2d b = u.position[loop[end % n]].head<2>();
    const Eigen::Vector2d c = u.position[loop[((k + 2) * n / 4) % n]].head<2>();
    const Eigen::Vector2d side = (b - a).normalized();
    EXPECT_NEAR(side.dot((c - b).normalized()), 0.0, 1e-8);
    for (size_t i = begin; i <= end; ++i) {
      const Eigen::Vector2d p = u.position[loop[i % n]].head<2>() - a;
      EXPECT_NEAR(side.x() * p.y() - side.y() * p.x(), 0.0, 1e-8 * size);
    }
  }
}

TEST(Uniformize, ConesCheckTheirInput) {
  const CompactMesh disk = test::cgal_mesh("nefertiti.off");
  EXPECT_THROW(cone_target(disk, {{disk.num_vertices(), 1.0}}), InvalidTargetError);
  EXPECT_THROW(cone_target(disk, {{3, 1.0}, {3, 2.0}}), InvalidTargetError);
  EXPECT_THROW(cone_target(disk, {{3, -1.0}}), InvalidTargetError);
  // Three right-angled corners: Gauss-Bonnet asks for positive curvature, an octant of a sphere.
  const std::vector<int>& loop = disk.boundary_loops()[0];
  const size_t n = loop.size();
  const TargetCurvature t =
      cone_target(disk, {{loop[0], kPi / 2}, {loop[n / 3], kPi / 2}, {loop[2 * n / 3], kPi / 2}});
  EXPECT_EQ(geometry_for_target(disk, t), Geometry::Spherical);
}

TEST(Uniformize, AutomaticChoiceByTopology) {
  const auto check = [](const CompactMesh& mesh, TargetPreset preset, Geometry geometry,
                        LayoutKind layout) {
    const auto [p, g] = automatic_preset(mesh);
    EXPECT_EQ(p, preset) << mesh.topology_name();
    EXPECT_EQ(g, geometry) << mesh.topology_name();
    EXPECT_EQ(planned_layout(mesh, p, g), layout) << mesh.topology_name();
  };
  check(test::cgal_mesh("nefertiti.off"), TargetPreset::UnitDisk, Geometry::Euclidean,
        LayoutKind::Plane);
  check(test::cgal_mesh("holes.off"), TargetPreset::UnitDisk, Geometry::Euclidean,
        LayoutKind::Plane);
  check(test::cgal_mesh("sphere.off"), TargetPreset::Zero, Geometry::Spherical, LayoutKind::Sphere);
  check(test::cgal_mesh("pipe.off"), TargetPreset::Zero, Geometry::Euclidean, LayoutKind::PlaneCut);
  check(test::cgal_mesh("eight.off"), TargetPreset::Zero, Geometry::Hyperbolic,
        LayoutKind::PoincareDisk);
}

TEST(Uniformize, FlatTorusReportsItsPeriodLattice) {
  const CompactMesh knot = test::cgal_mesh("knot1.off");
  const Uniformization u = uniformize(knot, {});
  ASSERT_TRUE(u.result.converged) << u.result.failure;
  EXPECT_EQ(u.layout_kind, LayoutKind::PlaneCut);
  ASSERT_EQ(u.periods.size(), 2u);
  // The two periods span a fundamental parallelogram of the torus's area, and every deck
  // transformation is a translation by an integer combination of them.
  const Complex w0 = u.periods[0], w1 = u.periods[1];
  const double det = std::imag(std::conj(w0) * w1);
  EXPECT_NEAR(std::abs(det), u.result.area, 1e-8 * u.result.area);
  for (const DiskIsometry& d : u.layout.deck) {
    EXPECT_LE(std::abs(d.a - 1.0), 1e-9);
    const double m = std::imag(std::conj(d.b) * w1) / det, n = std::imag(std::conj(w0) * d.b) / det;
    EXPECT_NEAR(m, std::round(m), 1e-8);
    EXPECT_NEAR(n, std::round(n), 1e-8);
  }
  EXPECT_LE(u.layout.relation_error, 1e-9);
}

TEST(Uniformize, TorusWithAHoleGetsAGeodesicBoundaryInH2) {
  const CompactMesh closed = test::torus(16, 8);
  std::vector<std::array<int, 3>> faces(closed.faces().begin() + 1, closed.faces().end());
  const CompactMesh holed(closed.positions(), faces);
  ASSERT_EQ(holed.genus(), 1);
  ASSERT_EQ(holed.num_boundary_loops(), 1);
  const Uniformization u = uniformize(holed, {});
  ASSERT_TRUE(u.result.converged) << u.result.failure;
  EXPECT_EQ(u.geometry, Geometry::Hyperbolic);
  EXPECT_EQ(u.layout_kind, LayoutKind::PoincareDisk);
  for (int v : holed.boundary_loops()[0]) {
    EXPECT_NEAR(u.result.curvature[v], 0.0, 1e-9);  // angle sum pi: geodesic boundary
  }
  EXPECT_NEAR(u.result.area, 2 * kPi, 1e-8);  // -2 pi chi
  EXPECT_LE(u.layout.closure_error, 1e-9);
  for (const auto& face : u.corners) {
    for (const auto& p : face) EXPECT_LT(p.norm(), 1.0);
  }
}

TEST(Uniformize, GenusTwoWithThreeHolesGetsGeodesicBoundariesInH2) {
  const CompactMesh mesh = test::cgal_mesh("double-torus-3-holes.off");
  ASSERT_EQ(mesh.genus(), 2);
  ASSERT_EQ(mesh.num_boundary_loops(), 3);
  const Uniformization u = uniformize(mesh, {});
  ASSERT_TRUE(u.result.converged) << u.result.failure;
  EXPECT_EQ(u.preset, TargetPreset::Zero);
  EXPECT_EQ(u.layout_kind, LayoutKind::PoincareDisk);
  for (const auto& loop : mesh.boundary_loops()) {
    for (int v : loop) EXPECT_NEAR(u.result.curvature[v], 0.0, 1e-9);  // geodesic boundary
  }
  EXPECT_NEAR(u.result.area, -2 * kPi * mesh.euler_characteristic(), 1e-7);  // 10 pi
  EXPECT_EQ(u.layout.cut.num_generators, 6);                                 // 2 g + b - 1
  EXPECT_LE(u.layout.closure_error, 1e-9);
  EXPECT_LE(u.layout.relation_error, 1e-8);
}

TEST(Uniformize, RequestsThatCannotBeMetAreRefused) {
  const CompactMesh sphere = test::cgal_mesh("sphere.off");
  UniformizationOptions o;
  o.preset = TargetPreset::UnitDisk;
  EXPECT_THROW(uniformize(sphere, o), InvalidTargetError);
  o.preset = TargetPreset::FreeBoundary;
  EXPECT_THROW(uniformize(sphere, o), InvalidTargetError);
  const CompactMesh disk = test::cgal_mesh("nefertiti.off");
  o.preset = TargetPreset::UnitDisk;
  o.geometry = Geometry::Hyperbolic;
  EXPECT_THROW(uniformize(disk, o), InvalidTargetError);
  o.geometry.reset();
  o.center_vertex = disk.boundary_loops()[0][0];
  try {
    uniformize(disk, o);
    ADD_FAILURE() << "a boundary centre vertex was accepted";
  } catch (const InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("lies on the boundary"), std::string::npos) << e.what();
  }
}

// A genus-6 machine part (gmsh's t13 lever, from the real-mesh set) in H2: the layout is grown
// from a central face along shortest paths, so no corner lies far out in the Poincare disk, where
// double precision runs out (from face 0 by breadth first it reached hyperbolic distance 10.5 and
// the surface group relations failed by 4e-4).
TEST(Uniformize, PoincareDiskLayoutStaysNearTheCentre) {
  const RepairedMesh repaired = real_mesh("gmsh-lever.stl");
  ASSERT_EQ(repaired.components.size(), 1u);
  const CompactMesh& mesh = repaired.components[0].mesh;
  ASSERT_EQ(mesh.genus(), 6);
  const Uniformization run = uniformize(mesh, UniformizationOptions());
  ASSERT_TRUE(run.converged()) << run.result.failure;
  ASSERT_EQ(run.geometry, Geometry::Hyperbolic);
  double farthest = 0;
  for (const auto& face : run.layout.corners) {
    for (const auto& p : face) farthest = std::max(farthest, 2 * std::atanh(p.head<2>().norm()));
  }
  EXPECT_LT(farthest, 8.0);
  EXPECT_LT(run.layout.relation_error, 1e-6);
  EXPECT_LT(run.layout.closure_error, 1e-9);
  EXPECT_TRUE(run.valid()) << run.layout_failure;
}

// A 3D printer's build plate (Cura, genus 97 after its non-manifold vertices are split): the
// hyperbolic Yamabe flow stalled on its triangles; with Ptolemy flips in the line search it
// converges. Its 80k flips cut the input into a common subdivision of a million thin pieces, which
// turned over near the rim of radius-12 charts: smaller charts draw every one.
TEST(Uniformize, HyperbolicFlowFlipsAcrossInvalidTrianglesAndDrawsThinPiecesInSmallerCharts) {
  const RepairedMesh repaired = real_mesh("cura-zav-maxpro.stl");
  const CompactMesh& mesh = repaired.components[0].mesh;
  ASSERT_EQ(mesh.genus(), 97);
  const Uniformization run = uniformize(mesh, UniformizationOptions());
  ASSERT_TRUE(run.converged()) << run.result.failure;
  EXPECT_EQ(run.geometry, Geometry::Hyperbolic);
  EXPECT_LE(run.result.residual, 1e-10);
  EXPECT_GT(run.totals.edge_flips, mesh.num_edges());
  ASSERT_TRUE(run.subdivision.has_value());
  EXPECT_GT(run.layout.num_charts(), 1);
  EXPECT_LT(run.layout.chart_radius, kChartRadius);
  // No delivered face is turned over, counted here: none has an orientation below what its
  // corners' rounding decides (those count as collapsed, and are warned of).
  EXPECT_EQ(turned_in_plane(run.corners, Rounding::Forgiven), 0);
  EXPECT_EQ(run.quality.flipped_faces, 0);
  EXPECT_TRUE(run.valid()) << run.layout_failure;
}

// SUMO's tram body (genus 0, 26 window loops): boundary vertices of one triangle, which a circle
// domain needs above 180 degrees (its Yamabe flow stalls on the surface and on its double); the
// Yamabe free boundary's triangles at the boundary degenerate. The automatic target then gives
// the tangential scheme's free boundary, saying why; an explicit target gets no other scheme.
TEST(Uniformize, AutomaticTargetTakesTheTangentialSchemeWhereYamabeGivesNoMap) {
  const RepairedMesh repaired = real_mesh("sumo-tram.obj");
  const CompactMesh& mesh = repaired.components[0].mesh;
  ASSERT_EQ(mesh.num_boundary_loops(), 26);
  const Uniformization run = uniformize(mesh, UniformizationOptions());
  ASSERT_TRUE(run.valid()) << run.result.failure << run.layout_failure;
  EXPECT_EQ(run.scheme, Scheme::Tangential);
  EXPECT_EQ(run.preset, TargetPreset::FreeBoundary);
  EXPECT_NE(run.scheme_instead.find("with the Yamabe scheme the disk target was not reached"),
            std::string::npos)
      << run.scheme_instead;
  EXPECT_NE(run.scheme_instead.find("the free-boundary target, tried instead, was not reached"),
            std::string::npos)
      << run.scheme_instead;
  EXPECT_NE(run.target_instead.find("its circles already touch"), std::string::npos)
      << run.target_instead;
  EXPECT_LE(run.result.residual, 1e-10);
  EXPECT_EQ(run.quality.flipped_faces, 0);
  EXPECT_EQ(turned_in_plane(run.corners, Rounding::Counted), 0);
  // An explicit target gets no other scheme.
  UniformizationOptions free;
  free.preset = TargetPreset::FreeBoundary;
  const Uniformization yamabe_free = uniformize(mesh, free);
  EXPECT_FALSE(yamabe_free.valid());
  EXPECT_EQ(yamabe_free.scheme, Scheme::Yamabe);
  EXPECT_TRUE(yamabe_free.scheme_instead.empty());
  UniformizationOptions disk;
  disk.preset = TargetPreset::UnitDisk;
  const Uniformization yamabe_disk = uniformize(mesh, disk);
  EXPECT_FALSE(yamabe_disk.valid());
  // Every attempt counts in the cost: the Yamabe disk and free boundary, then the tangential
  // scheme's disk and its free boundary.
  EXPECT_GE(run.totals.flows, yamabe_disk.totals.flows + yamabe_free.totals.flows + 2);
  EXPECT_GE(run.totals.newton_iterations,
            yamabe_disk.totals.newton_iterations + yamabe_free.totals.newton_iterations);
}

}  // namespace
}  // namespace ricci
