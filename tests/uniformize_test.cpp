// Target presets and the uniformization pipeline: the unit disk against the analytic conformal map
// of a square, circle domains, polygons from corner angles, automatic choices by topology, and the
// errors of requests that cannot be met.
#include "ricci/pipeline/uniformize.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "linear/blas_threads.h"
#include "no_new_threads.h"
#include "ricci/io/mesh_io.h"
#include "ricci/mesh/errors.h"
#include "ricci/pipeline/atlas.h"
#include "ricci/repair/repair.h"
#include "test_meshes.h"

namespace ricci {
namespace {

using Complex = std::complex<double>;

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

// The atlas's charts are packed after its flows and layouts: packing options that cannot pack are
// refused before them.
TEST(Uniformize, AnAtlasWhosePackingOptionsCannotPackIsRefusedFirst) {
  UniformizationOptions o;
  o.preset = TargetPreset::Atlas;
  o.packing.texture_size = 8;
  EXPECT_THROW(uniformize(test::ellipsoid(2), o), InvalidArgumentError);
  o.packing = PackingOptions();
  o.packing.padding = -1;
  EXPECT_THROW(uniformize(test::ellipsoid(2), o), InvalidArgumentError);
  // Not an atlas: nothing is packed, the options are not asked about.
  o.preset = TargetPreset::Automatic;
  EXPECT_TRUE(uniformize(test::ellipsoid(2), o).valid());
}

// A thin torus's flat metric is a long strip: alone, its atlas halves it (its own square packs
// fuller). Beside a sphere of over 31 times its area it is packed among the sphere's charts, whole;
// beside a smaller one it is halved as alone.
TEST(UniformizeMesh, ASmallPartsLongChartsStayWholeAmongTheOthers) {
  const CompactMesh ring = test::torus(64, 8, 3, 0.3);  // area about 35.5
  UniformizationOptions o;
  o.preset = TargetPreset::Atlas;
  EXPECT_GT(uniformize(ring, o).atlas.halvings, 0);
  const auto ring_beside_sphere = [&](double radius) {
    std::vector<Eigen::Vector3d> p = ring.positions();
    std::vector<std::array<int, 3>> f = ring.faces();
    const CompactMesh sphere = test::ellipsoid(3, radius, radius, radius);
    const int base = static_cast<int>(p.size());
    for (const auto& q : sphere.positions())
      p.push_back(q + Eigen::Vector3d(10 + 2 * radius, 0, 0));
    for (const auto& t : sphere.faces()) f.push_back({t[0] + base, t[1] + base, t[2] + base});
    const MeshUniformization both = uniformize_mesh(repair_mesh(p, f), o);
    EXPECT_TRUE(both.valid());
    for (size_t k = 0; k < both.components.size(); ++k) {
      if (both.mesh.components[k].mesh.genus() == 1) return both.components[k].atlas.halvings;
    }
    ADD_FAILURE() << "no torus among the components";
    return -1;
  };
  EXPECT_EQ(ring_beside_sphere(12), 0);  // the ring about 2 % of the area
  EXPECT_GT(ring_beside_sphere(2), 0);   // about 41 %
}

// Meshes side by side in one vertex and face list, each 4 units further along x.
RepairedMesh side_by_side(const std::vector<CompactMesh>& parts) {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::array<int, 3>> f;
  for (size_t k = 0; k < parts.size(); ++k) {
    const int base = static_cast<int>(p.size());
    for (const auto& q : parts[k].positions())
      p.push_back(q + Eigen::Vector3d(4.0 * static_cast<double>(k), 0, 0));
    for (const auto& t : parts[k].faces()) f.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  return repair_mesh(p, f);
}

// The components are uniformized two at a time (on two threads where the machine has two cores,
// OpenBLAS then on one thread): each as when alone with OpenBLAS on one thread, bit for bit.
TEST(UniformizeMesh, ComponentsRunTogetherAsEachAlone) {
  const std::vector<CompactMesh> parts = {test::ellipsoid(3, 1, 1.2, 0.8), test::square_grid(12),
                                          test::torus(24, 10), test::ellipsoid(2, 1, 0.5, 1)};
  for (const TargetPreset preset : {TargetPreset::Automatic, TargetPreset::Atlas}) {
    UniformizationOptions o;
    o.preset = preset;
    o.halve_long_charts = false;  // as for a small part among others
    const MeshUniformization all = uniformize_mesh(side_by_side(parts), o);
    ASSERT_EQ(all.components.size(), parts.size());
    EXPECT_TRUE(all.valid());
    for (size_t k = 0; k < parts.size(); ++k) {
      const Eigen::VectorXd& u = all.components[k].result.u;
      const detail::SingleThreadedBlas one_blas_thread;
      const Eigen::VectorXd alone = uniformize(all.mesh.components[k].mesh, o).result.u;
      ASSERT_EQ(u.size(), alone.size()) << "component " << k;
      EXPECT_EQ((u - alone).cwiseAbs().maxCoeff(), 0) << "component " << k;
    }
  }
}

// Where no thread can be made, one thread delivers the atlas two deliver: CGAL's lion head at 8
// cones, whose flow flips, whose charts are delivered on its faces beside a halving trial. (The
// run before the scope has started CHOLMOD's OpenMP threads, which the scope does not cover.)
TEST(Uniformize, WhereNoThreadCanBeMadeTheAtlasIsTheSame) {
  const CompactMesh lion = test::cgal_mesh("lion-head.off");
  UniformizationOptions o;
  o.preset = TargetPreset::Atlas;
  o.cone_placement.max_cones = 8;
  const detail::SingleThreadedBlas one_blas_thread;  // the same sums in both runs
  const Uniformization two = uniformize(lion, o);
  ASSERT_TRUE(two.valid());
  EXPECT_FALSE(two.result.flip_sequence.empty());
  EXPECT_GT(two.atlas.halvings, 0);
  const TextureCoordinates on_two = texture_coordinates(two);
  const test::NoNewThreads no_threads;
  ASSERT_TRUE(no_threads.held());
  ASSERT_THROW(std::thread([] {}).join(), std::system_error) << "the scope did not hold threads";
  const Uniformization one = uniformize(lion, o);
  ASSERT_TRUE(one.valid());
  const TextureCoordinates on_one = texture_coordinates(one);
  EXPECT_EQ((one.result.u - two.result.u).cwiseAbs().maxCoeff(), 0);
  ASSERT_EQ(on_one.wedge.size(), on_two.wedge.size());
  for (size_t f = 0; f < on_one.wedge.size(); ++f) {
    for (int k = 0; k < 3; ++k) ASSERT_EQ(on_one.wedge[f][k], on_two.wedge[f][k]) << f;
  }
}

// A vertex that delivered faces hold keeps its own results: here the repair joins each point's
// three copies and cuts the third triangle off again onto new copies, and the kept vertices 0
// and 1 hold the other triangles' faces while their own triangle went to the copies (in another
// component). Each delivered face's per-vertex positions are its corners.
TEST(UniformizeMesh, AVertexThatFacesHoldKeepsItsOwnResults) {
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0},
                                          {1, 0, 0}, {0, 0, 0}, {0.5, -1, 0},
                                          {0, 0, 0}, {1, 0, 0}, {0.5, 0, 1}};
  int cases = 0;
  for (const std::vector<std::array<int, 3>>& faces :
       {std::vector<std::array<int, 3>>{{0, 1, 2}, {3, 4, 5}, {6, 7, 8}},
        std::vector<std::array<int, 3>>{{3, 4, 5}, {6, 7, 8}, {0, 1, 2}}}) {
    const RepairedMesh repaired = repair_mesh(p, faces);
    ASSERT_EQ(repaired.components.size(), 2u);
    for (const MeshComponent& c : repaired.components) {
      for (int v : c.vertex) {
        const int r = repaired.represented_by[v];
        cases += r >= 0 && r != v;  // held, and said to take another vertex's results
      }
    }
    const MeshUniformization out = uniformize_mesh(repaired, UniformizationOptions());
    ASSERT_TRUE(out.valid());
    ASSERT_EQ(out.corners.size(), out.faces.size());
    ASSERT_EQ(out.position.size(), out.positions.size());
    ASSERT_EQ(out.texture.vertex.size(), out.positions.size());
    for (size_t f = 0; f < out.faces.size(); ++f) {
      const std::array<int, 3>& t = out.faces[f];
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(out.position[t[c]], out.corners[f][c]) << "face " << f << " corner " << c;
      }
      // The packing moves each piece by a similarity: a face's texture coordinates are its
      // corners' scaled alike along its three sides.
      std::array<double, 3> ratio{};
      for (int c = 0; c < 3; ++c) {
        const int a = t[c], b = t[(c + 1) % 3];
        ratio[c] = (out.texture.vertex[b] - out.texture.vertex[a]).norm() /
                   (out.corners[f][(c + 1) % 3] - out.corners[f][c]).norm();
      }
      EXPECT_NEAR(ratio[1], ratio[0], 1e-9 * ratio[0]) << "face " << f;
      EXPECT_NEAR(ratio[2], ratio[0], 1e-9 * ratio[0]) << "face " << f;
    }
  }
  EXPECT_GT(cases, 0) << "no vertex that faces hold is said to take another's results";
}

// Of several components that cannot be given the request, the first one's error is thrown, as
// when they ran one after the other.
TEST(UniformizeMesh, TheFirstFailingComponentIsNamed) {
  UniformizationOptions o;
  o.preset = TargetPreset::UnitDisk;  // no disk of a closed surface
  const RepairedMesh mesh = side_by_side(
      {test::square_grid(16), test::ellipsoid(2), test::square_grid(4), test::ellipsoid(1)});
  try {
    uniformize_mesh(mesh, o);
    ADD_FAILURE() << "closed components were given the unit disk";
  } catch (const InvalidTargetError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("component 1: ", 0), 0u) << e.what();
  }
}

// The run's wall time covers every stage it reports: the placements', flows', layouts' and
// packing's seconds sum to no more.
TEST(Uniformize, TheRunsSecondsCoverItsStages) {
  UniformizationOptions o;
  o.preset = TargetPreset::Atlas;
  const Uniformization run = uniformize(test::torus(48, 12), o);
  ASSERT_TRUE(run.valid());
  const AtlasResult::Seconds& s = run.atlas.seconds;
  const double stages = run.totals.times.total + run.atlas.placement.seconds +
                        (run.subdivision ? run.subdivision->seconds : 0) + s.charts + s.harmonic +
                        s.packing;
  EXPECT_GT(stages, 0);
  EXPECT_GE(run.seconds, stages);
}

// The caller's progress callback (a GUI's) is called on the caller's thread only, and cancelling
// there stops the flows.
TEST(UniformizeMesh, ProgressIsReportedOnTheCallersThread) {
  UniformizationOptions o;
  int calls = 0;
  bool elsewhere = false;
  const std::thread::id caller = std::this_thread::get_id();
  o.flow.progress = [&](const FlowProgress&) {
    elsewhere = elsewhere || std::this_thread::get_id() != caller;
    return ++calls < 2;
  };
  const MeshUniformization all = uniformize_mesh(
      side_by_side({test::ellipsoid(3), test::torus(24, 10), test::ellipsoid(3, 1, 2, 1)}), o);
  EXPECT_GE(calls, 2);
  EXPECT_FALSE(elsewhere);
  EXPECT_FALSE(all.converged());
}

}  // namespace
}  // namespace ricci
