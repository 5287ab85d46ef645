// Planar layout of flat metrics: it reproduces the metric, flips no triangle, and stays accurate
// on real meshes with obtuse triangles; surfaces other than disks are cut open.
#include "ricci/layout/layout.h"
#include "ricci/layout/lay_out.h"

#include <cmath>
#include <complex>

#include <gtest/gtest.h>

#include "layout/corners.h"
#include "layout/layout_methods.h"
#include "ricci/flow/ricci_flow.h"
#include "ricci/mesh/errors.h"
#include "test_meshes.h"

namespace ricci {
namespace {

// A point of a Poincare disk geodesic between two corners at distance 10 from the centre, 1e-3
// apart: on the geodesic to within a few roundings of its coordinates there (measured in long
// double, after the Moebius map that takes p to the centre and the geodesic to a ray), and where
// its hyperboloid weight puts it: sinh d(p, x) / sinh d(x, q) = t / (1 - t).
TEST(Layout, PointsOfADiskGeodesicStayOnItNearTheRim) {
  using LongComplex = std::complex<long double>;
  const auto move = [](LongComplex centre, LongComplex z) {
    return (z - centre) / (LongComplex(1) - std::conj(centre) * z);
  };
  const auto distance = [&](LongComplex a, LongComplex b) {
    return 2 * std::atanh(std::abs(move(a, b)));
  };
  const LongComplex p = std::polar(std::tanh(10.0L / 2), 0.3L);
  const LongComplex step = std::polar(std::tanh(1e-3L / 2), 1.1L);
  const LongComplex q = (step + p) / (LongComplex(1) + std::conj(p) * step);
  const Eigen::Vector3d pd(static_cast<double>(p.real()), static_cast<double>(p.imag()), 0);
  const Eigen::Vector3d qd(static_cast<double>(q.real()), static_cast<double>(q.imag()), 0);
  const LongComplex pl(pd.x(), pd.y()), ql(qd.x(), qd.y());
  for (double t : {0.1, 0.3, 0.5, 0.9}) {
    const Eigen::Vector3d x = detail::disk_geodesic_point(pd, qd, t);
    const LongComplex xl(x.x(), x.y());
    // One rounding of x's coordinates moves it this far in the hyperbolic metric.
    const long double rounding = 2 * 1.2e-16L / (1 - std::norm(xl));
    const long double off =
        distance(pl, xl) * std::abs(std::sin(std::arg(move(pl, xl)) - std::arg(move(pl, ql))));
    EXPECT_LE(off, 5 * rounding) << "t = " << t;
    const long double ratio = std::sinh(distance(pl, xl)) / std::sinh(distance(xl, ql));
    EXPECT_NEAR(static_cast<double>(ratio), t / (1 - t), 1e-7 * t / (1 - t)) << "t = " << t;
  }
}

TEST(Layout, FlatInputIsReproducedUpToARigidMotion) {
  const CompactMesh grid = test::square_grid(20);
  const Layout layout = lay_out(grid, Geometry::Euclidean, grid.input_lengths());
  const std::vector<Eigen::Vector3d> position = vertex_positions(grid, layout);
  EXPECT_EQ(layout.num_flipped_faces, 0);
  EXPECT_LE(layout.max_relative_length_error, 1e-11);
  // Distances between all vertex pairs (not only edges) match the input square.
  for (int i = 0; i < grid.num_vertices(); i += 37) {
    for (int j = 0; j < grid.num_vertices(); j += 41) {
      const double d_in = (grid.positions()[i] - grid.positions()[j]).norm();
      const double d_out = (position[i] - position[j]).norm();
      EXPECT_NEAR(d_in, d_out, 1e-12);
    }
  }
}

TEST(Layout, ConvergedMetricsOfRealDisksAreLaidOutExactly) {
  for (const char* name : {"nefertiti.off", "mushroom.off", "three_peaks.off"}) {
    const CompactMesh mesh = test::cgal_mesh(name);
    SchemeOptions options;
    options.scheme = Scheme::Tangential;  // always valid triangles, also on scans
    const FlowResult r = compute_ricci_flow(mesh, Geometry::Euclidean, options,
                                            TargetCurvature::free_boundary(mesh));
    const Layout layout = lay_out(mesh, Geometry::Euclidean, r.edge_lengths);
    EXPECT_EQ(layout.num_flipped_faces, 0) << name;
    EXPECT_LE(layout.max_relative_length_error, 1e-9) << name;
  }
}

TEST(Layout, DevelopedAndLeastSquaresLayoutsAgree) {
  // plane_layout develops face by face and falls back to the least-squares fit past a length
  // error; forced to the fit, it must give the same layout up to round-off (a disk and a torus).
  for (const char* name : {"nefertiti.off", "elk.off"}) {
    const CompactMesh mesh = test::cgal_mesh(name);
    SchemeOptions options;
    options.scheme = Scheme::Tangential;
    const FlowResult r = compute_ricci_flow(mesh, Geometry::Euclidean, options,
                                            TargetCurvature::free_boundary_or_zero(mesh));
    ASSERT_TRUE(r.converged) << name;
    const Layout developed = detail::plane_layout(mesh, r.edge_lengths, LinearSolverKind::Cholmod);
    const Layout fitted =
        detail::plane_layout(mesh, r.edge_lengths, LinearSolverKind::Cholmod, -1.0);
    EXPECT_LE(developed.max_relative_length_error, detail::kDevelopedLengthError) << name;
    EXPECT_LE(fitted.max_relative_length_error, 1e-8) << name;
    EXPECT_EQ(developed.num_flipped_faces, 0) << name;
    EXPECT_EQ(fitted.num_flipped_faces, 0) << name;
    // Both are the same flat metric: rigid motions apart, corner distances within a face agree.
    for (int f = 0; f < mesh.num_faces(); f += 7) {
      for (int c = 0; c < 3; ++c) {
        const auto &a = developed.corners[f], &b = fitted.corners[f];
        EXPECT_NEAR((a[c] - a[(c + 1) % 3]).norm(), (b[c] - b[(c + 1) % 3]).norm(),
                    1e-8 * (b[c] - b[(c + 1) % 3]).norm())
            << name << " face " << f;
      }
    }
  }
}

TEST(Layout, TextureCoordinatesFillTheUnitSquareKeepingAspect) {
  const std::vector<Eigen::Vector2d> p = {{-2, 1}, {2, 1}, {0, 2}};
  const auto uv = normalized_texture_coordinates(p);
  for (const auto& t : uv) {
    EXPECT_GE(t.minCoeff(), 0.0);
    EXPECT_LE(t.maxCoeff(), 1.0);
  }
  EXPECT_NEAR(uv[1].x() - uv[0].x(), 1.0, 1e-15);
  EXPECT_NEAR(uv[2].y() - uv[0].y(), 0.25, 1e-15);  // aspect 4:1 kept
}

TEST(Layout, SurfacesThatAreNotDisksAreCutOpen) {
  // A torus has no layout with one position per vertex: it is cut along two loops, and the
  // layout's corners on the two sides of the cut differ by the deck transformations.
  const CompactMesh torus = test::torus(8, 5);
  const FlowResult r =
      compute_ricci_flow(torus, Geometry::Euclidean, {}, TargetCurvature::zero(torus));
  const Layout layout = lay_out(torus, Geometry::Euclidean, r.edge_lengths);
  EXPECT_EQ(layout.cut.num_generators, 2);
  EXPECT_FALSE(layout.cut.paths.empty());
  EXPECT_EQ(layout.deck.size(), layout.cut.paths.size());
  EXPECT_EQ(layout.num_flipped_faces, 0);
  EXPECT_LE(layout.closure_error, 1e-9);
  EXPECT_THROW(lay_out(torus, Geometry::Euclidean, std::vector<double>(3, 1.0)),
               InvalidArgumentError);
}

}  // namespace
}  // namespace ricci
