// Connectivity, topology and every rejected kind of mesh, with messages that say what and where.
#include "ricci/mesh/compact_mesh.h"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "mesh/two_threads.h"
#include "ricci/mesh/errors.h"
#include "test_meshes.h"

namespace ricci {
namespace {

using Faces = std::vector<std::array<int, 3>>;
using Points = std::vector<Eigen::Vector3d>;

// Message of the InvalidMeshError thrown while building the mesh ("" if none).
std::string rejection(const Points& p, const Faces& f) {
  try {
    CompactMesh mesh(p, f);
  } catch (const InvalidMeshError& e) {
    return e.what();
  }
  return "";
}

Points square_points() {
  return {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
}

TEST(CompactMesh, TopologyOfGeneratedMeshes) {
  const CompactMesh disk = test::bumpy_disk(6);
  EXPECT_EQ(disk.euler_characteristic(), 1);
  EXPECT_EQ(disk.num_boundary_loops(), 1);
  EXPECT_EQ(disk.genus(), 0);
  EXPECT_EQ(disk.boundary_loops()[0].size(), 24u);
  EXPECT_EQ(disk.topology_name(), "disk");

  const CompactMesh torus = test::torus(8, 5);
  EXPECT_TRUE(torus.is_closed());
  EXPECT_EQ(torus.euler_characteristic(), 0);
  EXPECT_EQ(torus.genus(), 1);

  const CompactMesh sphere = test::ellipsoid(2);
  EXPECT_EQ(sphere.euler_characteristic(), 2);
  EXPECT_EQ(sphere.genus(), 0);
  EXPECT_EQ(sphere.topology_name(), "closed genus-0 surface");

  const CompactMesh eight = test::cgal_mesh("eight.off");
  EXPECT_EQ(eight.genus(), 2);
  const CompactMesh holes = test::cgal_mesh("holes.off");
  EXPECT_EQ(holes.num_boundary_loops(), 7);
  EXPECT_EQ(holes.genus(), 0);
}

TEST(CompactMesh, HalfedgesAndEdgesAreConsistent) {
  const CompactMesh mesh = test::cgal_mesh("nefertiti.off");
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    const int t = mesh.twin(h);
    const int e = mesh.face_edge(h / 3, h % 3);
    const int tail = mesh.halfedge_tail(h), head = mesh.halfedge_head(h);
    EXPECT_EQ(std::min(tail, head), mesh.edge_vertices(e)[0]);
    EXPECT_EQ(std::max(tail, head), mesh.edge_vertices(e)[1]);
    if (t < 0) {
      EXPECT_TRUE(mesh.is_boundary_edge(e));
      continue;
    }
    EXPECT_EQ(mesh.twin(t), h);
    EXPECT_EQ(mesh.halfedge_tail(t), mesh.halfedge_head(h));
    EXPECT_EQ(mesh.halfedge_head(t), mesh.halfedge_tail(h));
  }
  // Each boundary loop follows boundary edges.
  for (const auto& loop : mesh.boundary_loops()) {
    for (size_t i = 0; i < loop.size(); ++i) {
      EXPECT_TRUE(mesh.is_boundary_vertex(loop[i]));
    }
  }
}

TEST(CompactMesh, RejectsEmptyMesh) {
  EXPECT_NE(rejection({}, {}).find("at least one face"), std::string::npos);
}

TEST(CompactMesh, RejectsNonFiniteCoordinates) {
  Points p = square_points();
  p[2].y() = std::nan("");
  const std::string m = rejection(p, {{0, 1, 2}, {0, 2, 3}});
  EXPECT_NE(m.find("NaN or infinite"), std::string::npos) << m;
  EXPECT_NE(m.find("vertex 2"), std::string::npos) << m;
}

TEST(CompactMesh, RejectsDegenerateFaces) {
  Points p = square_points();
  p.emplace_back(2, 0, 0);  // collinear with 0 and 1
  std::string m = rejection(p, {{0, 1, 2}, {0, 2, 3}, {0, 1, 4}});
  EXPECT_NE(m.find("1 degenerate faces"), std::string::npos) << m;
  EXPECT_NE(m.find("face 2"), std::string::npos) << m;
  m = rejection(square_points(), {{0, 1, 2}, {0, 2, 2}});
  EXPECT_NE(m.find("degenerate"), std::string::npos) << m;
}

TEST(CompactMesh, RejectsUnreferencedVertices) {
  Points p = square_points();
  p.emplace_back(5, 5, 5);
  const std::string m = rejection(p, {{0, 1, 2}, {0, 2, 3}});
  EXPECT_NE(m.find("1 unreferenced vertices"), std::string::npos) << m;
  EXPECT_NE(m.find("vertex 4"), std::string::npos) << m;
}

TEST(CompactMesh, RejectsDuplicateFaces) {
  const std::string m = rejection(square_points(), {{0, 1, 2}, {0, 2, 3}, {1, 2, 0}});
  EXPECT_NE(m.find("duplicate faces"), std::string::npos) << m;
  EXPECT_NE(m.find("face 2"), std::string::npos) << m;
}

TEST(CompactMesh, RejectsNonManifoldEdges) {
  Points p = square_points();
  p.emplace_back(0.5, 0.5, 1);
  const std::string m = rejection(p, {{0, 1, 2}, {0, 2, 3}, {2, 0, 4}});
  EXPECT_NE(m.find("non-manifold edges"), std::string::npos) << m;
  EXPECT_NE(m.find("edge (0, 2)"), std::string::npos) << m;
}

TEST(CompactMesh, RejectsNonManifoldVertices) {
  // Two triangles sharing only vertex 0 (a bow tie).
  const Points p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  const std::string m = rejection(p, {{0, 1, 2}, {0, 3, 4}});
  EXPECT_NE(m.find("non-manifold vertices"), std::string::npos) << m;
  EXPECT_NE(m.find("vertex 0"), std::string::npos) << m;
}

TEST(CompactMesh, RejectsInconsistentOrientation) {
  const std::string m = rejection(square_points(), {{0, 1, 2}, {0, 3, 2}});
  EXPECT_NE(m.find("opposite orientations"), std::string::npos) << m;
}

TEST(CompactMesh, RejectsSeveralComponents) {
  Points p = square_points();
  for (const auto& q : square_points()) p.push_back(q + Eigen::Vector3d(3, 0, 0));
  const std::string m = rejection(p, {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}, {4, 7, 5}});
  EXPECT_NE(m.find("2 connected components"), std::string::npos) << m;
}

// Loops split over two threads (mesh/two_threads.h): a half that throws (bad_alloc in a long
// loop) leaves the other to end, and its exception reaches the caller, not std::terminate.
TEST(TwoThreads, AnExceptionOfEitherHalfReachesTheCaller) {
  for (const int throwing : {0, 1}) {
    std::atomic<int> done{0};
    EXPECT_THROW(detail::in_two_halves(
                     100,
                     [&](int part, int begin, int end) {
                       if (part == throwing) throw std::runtime_error("this half");
                       done += end - begin;
                     },
                     10),
                 std::runtime_error);
    EXPECT_EQ(done, 50) << "half " << throwing;
  }
}

}  // namespace
}  // namespace ricci
