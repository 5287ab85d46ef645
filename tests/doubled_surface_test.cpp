// The flow on the surface doubled along its boundary: the double's connectivity and target, and
// the half delivered from it where the surface's own triangulation stalls at the boundary.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "layout_measures.h"
#include "pipeline/doubled_surface.h"
#include "ricci/flow/presets.h"
#include "ricci/io/mesh_io.h"
#include "ricci/pipeline/uniformize.h"
#include "ricci/repair/repair.h"
#include "test_meshes.h"

namespace ricci {
namespace {

void expect_double_of(const CompactMesh& half) {
  const CompactMesh twice = CompactMesh::doubled(half);
  int boundary_vertices = 0;
  for (int v = 0; v < half.num_vertices(); ++v) boundary_vertices += half.is_boundary_vertex(v);
  EXPECT_TRUE(twice.is_closed());
  EXPECT_EQ(twice.num_vertices(), 2 * half.num_vertices() - boundary_vertices);
  EXPECT_EQ(twice.num_faces(), 2 * half.num_faces());
  EXPECT_EQ(twice.euler_characteristic(), 2 * half.euler_characteristic());
  EXPECT_EQ(twice.genus(), 2 * half.genus() + half.num_boundary_loops() - 1);
  for (int e = 0; e < half.num_edges(); ++e) {
    EXPECT_EQ(twice.edge_vertices(e), half.edge_vertices(e)) << "edge " << e;
    EXPECT_DOUBLE_EQ(twice.input_lengths()[e], half.input_lengths()[e]);
  }
  for (int f = 0; f < half.num_faces(); ++f) EXPECT_EQ(twice.faces()[f], half.faces()[f]);
}

// A flat annulus of `rings` x n quadrilaterals, each split in two.
CompactMesh annulus(int rings, int n) {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::array<int, 3>> f;
  for (int i = 0; i <= rings; ++i) {
    for (int j = 0; j < n; ++j) {
      const double r = 1 + static_cast<double>(i) / rings, t = 2 * kPi * j / n;
      p.emplace_back(r * std::cos(t), r * std::sin(t), 0);
    }
  }
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < n; ++j) {
      const int a = i * n + j, b = i * n + (j + 1) % n, c = a + n, d = b + n;
      f.push_back({a, b, d});
      f.push_back({a, d, c});
    }
  }
  return CompactMesh(p, f);
}

TEST(DoubledSurface, TwoCopiesGluedAlongTheBoundary) {
  expect_double_of(test::bumpy_disk(5));
  expect_double_of(annulus(3, 12));  // the double of an annulus is a torus
  EXPECT_EQ(CompactMesh::doubled(annulus(3, 12)).genus(), 1);
  // A square of two triangles: its diagonal joins two boundary vertices, so the double has two
  // edges between them (the diagonal and its mirror image), and four faces on four vertices.
  const CompactMesh square({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}});
  expect_double_of(square);
  const CompactMesh twice = CompactMesh::doubled(square);
  EXPECT_EQ(twice.num_edges(), 6);
  int diagonals = 0;
  for (int e = 0; e < twice.num_edges(); ++e)
    diagonals += twice.edge_vertices(e) == std::array<int, 2>{0, 2};
  EXPECT_EQ(diagonals, 2);
}

TEST(DoubledSurface, TargetIsTwiceTheBoundaryCurvature) {
  const CompactMesh half = test::bumpy_disk(6);
  const CompactMesh twice = CompactMesh::doubled(half);
  const TargetCurvature disk = circle_boundary_target(half, half.input_lengths(), 0);
  const TargetCurvature t = detail::doubled_target(half, twice, disk);
  // Gauss-Bonnet on the double (a sphere): 4 pi.
  EXPECT_NEAR(t.curvature.sum(), 4 * kPi, 1e-9);
  EXPECT_NO_THROW(check_target(twice, Geometry::Euclidean, t));
  const TargetCurvature fixed =
      detail::doubled_target(half, twice, TargetCurvature::free_boundary(half));
  for (int v = 0; v < twice.num_vertices(); ++v) {
    EXPECT_EQ(fixed.is_fixed(v), v < half.num_vertices() && half.is_boundary_vertex(v));
  }
}

// DRC-Hubo's hip collision hull (dart-doc, BSD-2-clause): merged convex pieces whose repaired
// components include disks that the disk target stalls on at the boundary.
TEST(DoubledSurface, DisksThatStallAtTheBoundaryAreMappedOnTheDouble) {
  const MeshFile file = read_mesh_file(RICCI_REAL_MESH_DIR "/dart-drchubo-lhr.stl");
  const RepairedMesh repaired = repair_mesh(file.positions, file.triangles);
  int doubled = 0;
  for (const MeshComponent& component : repaired.components) {
    const CompactMesh& mesh = component.mesh;
    if (mesh.is_closed()) continue;
    const Uniformization run = uniformize(mesh, {});
    EXPECT_TRUE(run.valid()) << run.result.failure << run.layout_failure;
    if (!run.doubled) continue;
    ++doubled;
    // Converged: to the tolerance, or where double precision stops short of it, within the floor
    // that the angle sums' round-off sets on the intrinsic Delaunay triangulation (whose faces
    // include the input's slivers: a floor of 1.6e-8 here).
    EXPECT_LE(run.result.residual, std::max(1e-9, run.result.attainable_residual));
    EXPECT_LE(run.result.attainable_residual, 1e-7);
    // Checked here: every delivered face counter-clockwise, the outer loop on the unit circle.
    for (const auto& t : run.corners) {
      const Eigen::Vector3d a = t[1] - t[0], b = t[2] - t[0];
      EXPECT_GT(a.x() * b.y() - a.y() * b.x(), 0);
    }
    for (int v : mesh.boundary_loops()[0]) EXPECT_NEAR(run.position[v].head<2>().norm(), 1, 1e-6);
    // The delivered mesh is the input surface: its faces cover the input's area, and new
    // vertices lie on input edges.
    const std::vector<Eigen::Vector3d>& p =
        run.subdivision ? run.subdivision->positions : mesh.positions();
    const std::vector<std::array<int, 3>>& faces =
        run.subdivision ? run.subdivision->faces : mesh.faces();
    double area = 0;
    for (const auto& t : faces) area += 0.5 * (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).norm();
    EXPECT_NEAR(area, mesh.input_area(), 1e-9 * mesh.input_area());
    // The map is conformal: the double flows in the canonical class of its intrinsic Delaunay
    // triangulation. In the input triangulation's class its pieces had QC p95 2.36, now 1.05.
    std::vector<double> qc;
    for (size_t f = 0; f < faces.size(); ++f) {
      qc.push_back(
          test::quasi_conformal({p[faces[f][0]], p[faces[f][1]], p[faces[f][2]]}, run.corners[f]));
    }
    EXPECT_LE(test::percentile(qc, 0.95), 1.2);
    if (run.subdivision) {
      const CommonSubdivision& sub = *run.subdivision;
      for (size_t i = 0; i < sub.vertex_input_edge.size(); ++i) {
        const auto [a, b] = mesh.edge_vertices(sub.vertex_input_edge[i]);
        const double s = sub.vertex_edge_parameter[i];
        const Eigen::Vector3d on_edge = (1 - s) * mesh.positions()[a] + s * mesh.positions()[b];
        EXPECT_LE((sub.positions[mesh.num_vertices() + i] - on_edge).norm(), 1e-12);
      }
    }
  }
  EXPECT_GE(doubled, 1);
}

// Barrett WAM link 6 (dart-doc, BSD-2-clause): a CAD part of genus 1 with 35 boundary loops,
// whose hyperbolic metric with geodesic boundary stalls at the boundary on its own triangulation.
TEST(DoubledSurface, HyperbolicSurfacesWithBoundaryAreMappedOnTheDouble) {
  const MeshFile file = read_mesh_file(RICCI_REAL_MESH_DIR "/dart-wam6.STL");
  const RepairedMesh repaired = repair_mesh(file.positions, file.triangles);
  ASSERT_EQ(repaired.components.size(), 1u);
  const CompactMesh& mesh = repaired.components[0].mesh;
  const Uniformization run = uniformize(mesh, {});
  ASSERT_TRUE(run.doubled) << run.result.failure;
  EXPECT_TRUE(run.valid()) << run.layout_failure;
  EXPECT_EQ(run.geometry, Geometry::Hyperbolic);
  EXPECT_EQ(run.layout_kind, LayoutKind::PoincareDisk);
  EXPECT_LE(run.result.residual, 1e-9);
  // The half's curvature: Gauss-Bonnet with geodesic boundary, sum K - area = 2 pi chi.
  EXPECT_NEAR(run.result.curvature.sum() - run.result.area, 2 * kPi * mesh.euler_characteristic(),
              1e-7);
  ASSERT_TRUE(run.subdivision.has_value());
  const CommonSubdivision& sub = *run.subdivision;
  ASSERT_EQ(run.corners.size(), sub.faces.size());
  double area = 0;
  for (size_t f = 0; f < sub.faces.size(); ++f) {
    const auto& t = run.corners[f];
    const Eigen::Vector3d a = t[1] - t[0], b = t[2] - t[0];
    EXPECT_GT(a.x() * b.y() - a.y() * b.x(), 0) << "face " << f;
    for (const auto& p : t) EXPECT_LT(p.head<2>().norm(), 1);
    const auto& p = sub.positions;
    const auto& v = sub.faces[f];
    area += 0.5 * (p[v[1]] - p[v[0]]).cross(p[v[2]] - p[v[0]]).norm();
  }
  EXPECT_NEAR(area, mesh.input_area(), 1e-9 * mesh.input_area());
}

}  // namespace
}  // namespace ricci
