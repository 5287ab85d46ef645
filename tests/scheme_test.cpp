// Scheme presets and the Appendix initialization: the initial metric reproduces the input
// lengths (inversive distance, Yamabe, virtual radius, mixed) in E2, H2 and S2.
#include "ricci/flow/scheme.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "flow/metric.h"
#include "ricci/mesh/errors.h"
#include "test_meshes.h"

namespace ricci {
namespace {

const Geometry kGeometries[] = {Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical};

double max_relative_length_error(const CompactMesh& mesh, const ConformalStructure& s) {
  const MetricState state = evaluate_metric(mesh, s, s.u0);
  double err = 0;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (!state.edges[e].valid) return INFINITY;
    err = std::max(
        err, std::abs(state.edges[e].length / (s.length_scale * mesh.input_lengths()[e]) - 1));
  }
  return err;
}

TEST(Scheme, NamesRoundTrip) {
  for (Scheme s : {Scheme::Tangential, Scheme::Thurston, Scheme::InversiveDistance, Scheme::Yamabe,
                   Scheme::VirtualRadius, Scheme::Mixed}) {
    EXPECT_EQ(scheme_from_string(to_string(s)), s);
  }
  EXPECT_THROW(scheme_from_string("ricci"), InvalidArgumentError);
  EXPECT_THROW(geometry_from_string("elliptic"), InvalidArgumentError);
}

TEST(Scheme, InitialMetricReproducesInputLengths) {
  const CompactMesh mesh = test::cgal_mesh("nefertiti.off");
  std::vector<int> eps(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) eps[v] = v % 3 - 1;
  for (Geometry g : kGeometries) {
    for (Scheme scheme :
         {Scheme::InversiveDistance, Scheme::Yamabe, Scheme::VirtualRadius, Scheme::Mixed}) {
      SchemeOptions options;
      options.scheme = scheme;
      options.eps = eps;
      // H2 and S2 get a scaled copy of the input lengths (spherical perimeters below pi).
      const double scale = g == Geometry::Euclidean ? 1.0 : 0.01;
      const ConformalStructure s = initialize_scheme(mesh, g, options, scale);
      EXPECT_LE(max_relative_length_error(mesh, s), 1e-12)
          << to_string(g) << " " << to_string(scheme);
      EXPECT_TRUE(reproduces_input_lengths(scheme));
    }
  }
}

// The lengths-only test of the walk to a start: never false where the metric is valid, and false
// wherever a triangle inequality fails (on growing random conformal factors: from every metric
// valid to most faces invalid, in every geometry and scheme).
TEST(Scheme, TheLengthsOnlyTestAgreesWithTheMetricsValidity) {
  const CompactMesh mesh = test::cgal_mesh("nefertiti.off");
  std::vector<int> eps(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) eps[v] = v % 3 - 1;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> half(-0.5, 0.5);
  Eigen::VectorXd noise(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) noise[v] = half(random);
  int valid = 0, inequality_fails = 0;
  for (Geometry g : kGeometries) {
    for (Scheme scheme : {Scheme::Yamabe, Scheme::InversiveDistance, Scheme::Mixed}) {
      SchemeOptions options;
      options.scheme = scheme;
      options.eps = eps;
      const ConformalStructure s =
          initialize_scheme(mesh, g, options, g == Geometry::Euclidean ? 1.0 : 0.01);
      for (double size : {0.0, 0.01, 0.1, 0.5, 2.0, 8.0}) {
        const Eigen::VectorXd u = s.u0 + size * noise;
        const MetricState state = evaluate_metric(mesh, s, u);
        bool inequalities = state.num_invalid_edges == 0;
        for (int f = 0; f < mesh.num_faces() && inequalities; ++f) {
          const auto& e = mesh.face_edges(f);
          inequalities = is_valid_triangle(
              g, {state.edges[e[0]].length, state.edges[e[1]].length, state.edges[e[2]].length});
        }
        const bool admitted = lengths_admit_triangles(mesh, g, evaluate_lengths(mesh, s, u));
        EXPECT_EQ(admitted, inequalities)
            << to_string(g) << " " << to_string(scheme) << " " << size;
        EXPECT_TRUE(admitted || !state.valid()) << to_string(g) << " " << size;
        valid += state.valid();
        inequality_fails += state.num_invalid_edges == 0 && !inequalities;
      }
    }
  }
  EXPECT_GT(valid, 0);
  EXPECT_GT(inequality_fails, 0);  // edges valid, a triangle inequality failing
}

TEST(Scheme, EpsAndEtaPresets) {
  const CompactMesh mesh = test::torus(8, 5);
  SchemeOptions options;
  options.scheme = Scheme::Tangential;
  ConformalStructure s = initialize_scheme(mesh, Geometry::Euclidean, options);
  for (int v = 0; v < mesh.num_vertices(); ++v) EXPECT_EQ(s.eps[v], 1);
  for (double eta : s.eta) EXPECT_EQ(eta, 1.0);

  options.scheme = Scheme::Thurston;
  options.intersection_angle = kPi / 4;
  s = initialize_scheme(mesh, Geometry::Hyperbolic, options, 0.3);
  for (double eta : s.eta) EXPECT_DOUBLE_EQ(eta, std::cos(kPi / 4));

  options.scheme = Scheme::InversiveDistance;
  s = initialize_scheme(mesh, Geometry::Euclidean, options);
  // r = min incident length / 3 keeps the circles apart: eta > 1.
  for (double eta : s.eta) EXPECT_GT(eta, 1.0);

  options.scheme = Scheme::Yamabe;
  s = initialize_scheme(mesh, Geometry::Euclidean, options);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    EXPECT_EQ(s.eps[v], 0);
    EXPECT_EQ(s.u0[v], 0.0);
  }
  options.scheme = Scheme::VirtualRadius;
  s = initialize_scheme(mesh, Geometry::Spherical, options, 0.3);
  for (int v = 0; v < mesh.num_vertices(); ++v) EXPECT_EQ(s.eps[v], -1);
  for (double eta : s.eta) EXPECT_GT(eta, 0.0);
}

TEST(Scheme, TangentialRadiiFitTheInputTriangles) {
  // On an equilateral-ish mesh the incircle radii are about half the edge length.
  const CompactMesh mesh = test::ellipsoid(2);
  SchemeOptions options;
  options.scheme = Scheme::Tangential;
  const ConformalStructure s = initialize_scheme(mesh, Geometry::Euclidean, options);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [i, j] = mesh.edge_vertices(e);
    const double l = std::exp(s.u0[i]) + std::exp(s.u0[j]);
    EXPECT_NEAR(l / mesh.input_lengths()[e], 1.0, 0.25);
  }
}

TEST(Scheme, RejectsBadOptions) {
  const CompactMesh mesh = test::torus(8, 5);
  SchemeOptions options;
  options.scheme = Scheme::Thurston;
  options.intersection_angle = 2.0;  // > pi/2
  EXPECT_THROW(initialize_scheme(mesh, Geometry::Euclidean, options), InvalidArgumentError);
  options.scheme = Scheme::Mixed;
  options.eps = {1, 0};
  try {
    initialize_scheme(mesh, Geometry::Euclidean, options);
    FAIL() << "expected InvalidArgumentError";
  } catch (const InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("2 values but the mesh has 40 vertices"),
              std::string::npos)
        << e.what();
  }
  options.eps.assign(mesh.num_vertices(), 1);
  options.eps[7] = 2;
  try {
    initialize_scheme(mesh, Geometry::Euclidean, options);
    FAIL() << "expected InvalidArgumentError";
  } catch (const InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 7"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ricci
