// Layouts in the model spaces, checked with the models' own geometry (not the developer's):
// angle sums and areas measured on the laid-out points, the cut's two sides glued by isometries.
#include "ricci/layout/lay_out.h"
#include "ricci/layout/layout.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "ricci/flow/ricci_flow.h"
#include "test_meshes.h"

namespace ricci {
namespace {

using Complex = std::complex<double>;

// The angle at corner c of face f, measured in the model at the laid-out points.
double measured_angle(const Layout& layout, int f, int c) {
  const Eigen::Vector3d& a = layout.corners[f][c];
  const Eigen::Vector3d& b = layout.corners[f][(c + 1) % 3];
  const Eigen::Vector3d& d = layout.corners[f][(c + 2) % 3];
  switch (layout.geometry) {
    case Geometry::Euclidean:
      return std::acos((b - a).normalized().dot((d - a).normalized()));
    case Geometry::Hyperbolic: {
      // Moved to the origin, geodesics through a are straight.
      const Complex z(a.x(), a.y());
      const auto move = [&](const Eigen::Vector3d& p) {
        const Complex w(p.x(), p.y());
        return (w - z) / (1.0 - std::conj(z) * w);
      };
      return std::abs(std::arg(move(d) / move(b)));
    }
    case Geometry::Spherical: {
      const Eigen::Vector3d tb = (b - a.dot(b) * a).normalized();
      const Eigen::Vector3d td = (d - a.dot(d) * a).normalized();
      return std::acos(std::clamp(tb.dot(td), -1.0, 1.0));
    }
  }
  return 0;
}

// Per vertex: the sum of the measured angles; and the total area from the angles.
struct Measured {
  Eigen::VectorXd angle_sum;
  double area = 0;
};

Measured measure(const Triangulation& mesh, const Layout& layout) {
  Measured m;
  m.angle_sum = Eigen::VectorXd::Zero(mesh.num_vertices());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    double sum = 0;
    for (int c = 0; c < 3; ++c) {
      const double a = measured_angle(layout, f, c);
      m.angle_sum[mesh.face_vertex(f, c)] += a;
      sum += a;
    }
    m.area += std::abs(sum - kPi);  // excess (S2) or defect (H2)
  }
  return m;
}

double hyperbolic_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  const Complex z(p.x(), p.y()), w(q.x(), q.y());
  return 2 * std::atanh(std::abs(z - w) / std::abs(1.0 - std::conj(z) * w));
}

TEST(CutGraph, DisksAndSpheresNeedNoCutAndATorusTwoLoops) {
  EXPECT_TRUE(cut_to_disk(test::bumpy_disk(8)).paths.empty());
  EXPECT_TRUE(cut_to_disk(test::ellipsoid(2)).paths.empty());
  const CompactMesh torus = test::torus(12, 8);
  const CutGraph cut = cut_to_disk(torus);
  EXPECT_EQ(cut.num_generators, 2);
  // A pruned cut graph of a torus is two loops at a vertex (2 paths) or a theta graph (3).
  EXPECT_GE(cut.paths.size(), 2u);
  EXPECT_LE(cut.paths.size(), 3u);
  // The paths hold every cut edge once.
  int cut_edges = 0;
  for (const CutPath& p : cut.paths) {
    EXPECT_EQ(p.vertices.size(), p.edges.size() + 1);
    for (int e : p.edges) EXPECT_TRUE(cut.cut[e]);
    cut_edges += static_cast<int>(p.edges.size());
  }
  int marked = 0;
  for (char c : cut.cut) marked += c;
  EXPECT_EQ(cut_edges, marked);
}

TEST(Layout, FlatTorusWedgesDifferByTheTwoPeriods) {
  const CompactMesh torus = test::torus(24, 12);
  SchemeOptions scheme;
  FlowOptions options;
  const FlowResult r =
      compute_ricci_flow(torus, Geometry::Euclidean, scheme, TargetCurvature::zero(torus), options);
  const Triangulation t = result_triangulation(torus, r);
  const Layout layout = lay_out(t, Geometry::Euclidean, r.edge_lengths);
  EXPECT_EQ(layout.num_flipped_faces, 0);
  EXPECT_LE(layout.closure_error, 1e-9);
  const Measured m = measure(t, layout);
  EXPECT_LE((m.angle_sum.array() - 2 * kPi).abs().maxCoeff(), 1e-9);
  // Every deck transformation is a translation, and two of them span the plane.
  ASSERT_GE(layout.deck.size(), 2u);
  double span = 0;
  for (const DiskIsometry& d : layout.deck) {
    EXPECT_LE(std::abs(d.a - 1.0), 1e-9);
    for (const DiskIsometry& e : layout.deck)
      span = std::max(span, std::abs(std::imag(std::conj(d.b) * e.b)));
  }
  EXPECT_GT(span, 1e-3 * r.area);
  EXPECT_LE(surface_group_relation_error(t, layout), 1e-9);  // the periods commute
}

TEST(Layout, GenusTwoFundamentalDomainInThePoincareDisk) {
  const CompactMesh eight = test::cgal_mesh("eight.off");
  SchemeOptions scheme;
  const FlowResult r =
      compute_ricci_flow(eight, Geometry::Hyperbolic, scheme, TargetCurvature::zero(eight));
  const Triangulation t = result_triangulation(eight, r);
  const Layout layout = lay_out(t, Geometry::Hyperbolic, r.edge_lengths);
  EXPECT_EQ(layout.cut.num_generators, 4);
  EXPECT_EQ(layout.num_flipped_faces, 0);
  EXPECT_LE(layout.closure_error, 1e-8);
  for (const auto& face : layout.corners) {
    for (const auto& p : face) EXPECT_LT(p.norm(), 1.0);
  }
  const Measured m = measure(t, layout);
  EXPECT_LE((m.angle_sum.array() - 2 * kPi).abs().maxCoeff(), 1e-8);
  EXPECT_NEAR(m.area, 4 * kPi, 1e-7);  // -2 pi chi
  // Both sides of every cut edge have the edge's hyperbolic length, and the deck transformations
  // are isometries of the disk (|a|^2 - |b|^2 = 1) that are not the identity.
  for (const CutPath& path : layout.cut.paths) {
    for (int e : path.edges) {
      const auto [f, g] = t.edge_faces(e);
      for (int face : {f, g}) {
        int ca = 0, cb = 0;
        for (int c = 0; c < 3; ++c) {
          if (t.face_vertex(face, c) == t.edge_vertices(e)[0]) ca = c;
          if (t.face_vertex(face, c) == t.edge_vertices(e)[1]) cb = c;
        }
        EXPECT_NEAR(hyperbolic_distance(layout.corners[face][ca], layout.corners[face][cb]),
                    r.edge_lengths[e], 1e-8);
      }
    }
  }
  for (const DiskIsometry& d : layout.deck) {
    EXPECT_NEAR(std::norm(d.a) - std::norm(d.b), 1.0, 1e-8);
    EXPECT_GT(std::abs(d.b), 0.1);
  }
  // The surface group's relations: around every node of the cut the deck maps compose to the
  // identity; a deck map off by a small rotation breaks them.
  EXPECT_LE(surface_group_relation_error(t, layout), 1e-8);
  Layout broken = layout;
  broken.deck[0] = broken.deck[0] * DiskIsometry{Geometry::Hyperbolic, std::polar(1.0, 0.01), 0.0};
  EXPECT_GT(surface_group_relation_error(t, broken), 1e-3);
}

TEST(Layout, RoundSphereOnTheUnitSphereCentred) {
  const CompactMesh blob = test::ellipsoid(3, 1.0, 0.7, 0.5);
  SchemeOptions scheme;
  const FlowResult r =
      compute_ricci_flow(blob, Geometry::Spherical, scheme, TargetCurvature::zero(blob));
  const Triangulation t = result_triangulation(blob, r);
  const Layout layout = lay_out(t, Geometry::Spherical, r.edge_lengths);
  EXPECT_TRUE(layout.cut.paths.empty());
  EXPECT_EQ(layout.num_flipped_faces, 0);
  EXPECT_LE(layout.closure_error, 1e-9);
  const Measured m = measure(t, layout);
  EXPECT_LE((m.angle_sum.array() - 2 * kPi).abs().maxCoeff(), 1e-9);
  EXPECT_NEAR(m.area, 4 * kPi, 1e-9);
  const std::vector<Eigen::Vector3d> centred = center_on_sphere(vertex_positions(t, layout));
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& x : centred) {
    EXPECT_NEAR(x.norm(), 1.0, 1e-12);
    centroid += x;
  }
  EXPECT_LE(centroid.norm() / static_cast<double>(centred.size()), 1e-10);
  int flipped = 0;
  for (const auto& f : t.faces())
    flipped += !(centred[f[0]].dot(centred[f[1]].cross(centred[f[2]])) > 0);
  EXPECT_EQ(flipped, 0);
}

}  // namespace
}  // namespace ricci
