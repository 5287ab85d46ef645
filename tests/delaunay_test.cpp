// Edge flips: the flip routine on its own (Delaunay afterwards, metric kept, a valid
// triangulation), and Yamabe with flips, whose result is discretely conformal to the input in
// the Ptolemy sense, checked by replaying the flips with an independent Ptolemy rule; Ptolemy
// flips from lengths that violate the triangle inequality, and the line search that uses them.
#include "flow/delaunay.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "flow/flow_steps.h"
#include "flow/metric.h"
#include "ricci/flow/ricci_flow.h"
#include "test_meshes.h"

namespace ricci {
namespace {

// A triangulation is valid: faces of three distinct vertices, no self-loops, each face's edges
// between its corners, twins consistent with edge endpoints. Two edges may join the same pair of
// vertices (intrinsic triangulations can need them).
void expect_valid_triangulation(const Triangulation& t) {
  for (int e = 0; e < t.num_edges(); ++e) {
    const auto [a, b] = t.edge_vertices(e);
    EXPECT_NE(a, b) << "self-loop at edge " << e;
  }
  for (int h = 0; h < t.num_halfedges(); ++h) {
    std::array<int, 2> ends = {t.halfedge_tail(h), t.halfedge_head(h)};
    std::sort(ends.begin(), ends.end());
    EXPECT_EQ(t.edge_vertices(t.face_edge(h / 3, h % 3)), ends) << "halfedge " << h;
  }
  for (int f = 0; f < t.num_faces(); ++f) {
    EXPECT_NE(t.face_vertex(f, 0), t.face_vertex(f, 1));
    EXPECT_NE(t.face_vertex(f, 1), t.face_vertex(f, 2));
    EXPECT_NE(t.face_vertex(f, 2), t.face_vertex(f, 0));
  }
  for (int h = 0; h < t.num_halfedges(); ++h) {
    const int tw = t.twin(h);
    if (tw < 0) continue;
    EXPECT_EQ(t.twin(tw), h);
    EXPECT_EQ(t.halfedge_tail(tw), t.halfedge_head(h));
    EXPECT_EQ(t.face_edge(tw / 3, tw % 3), t.face_edge(h / 3, h % 3));
  }
}

TEST(Delaunay, FlipsOfThePackingSchemesKeepTheMetric) {
  // The input metric of a scan (inversive distance reproduces it exactly) is far from Delaunay.
  for (Geometry g : {Geometry::Euclidean, Geometry::Hyperbolic}) {
    const CompactMesh mesh = test::cgal_mesh("mannequin-devil.off");
    SchemeOptions options;
    options.scheme = Scheme::InversiveDistance;
    ConformalStructure s =
        initialize_scheme(mesh, g, options, g == Geometry::Euclidean ? 1.0 : 0.02);
    IntrinsicTriangulation t(mesh);
    MetricState state = evaluate_metric(t, s, s.u0);
    ASSERT_TRUE(state.valid());
    const Eigen::VectorXd k_before = curvature(t, state);
    const double area_before = total_area(t, g, state);
    int not_delaunay = 0;
    for (int e = 0; e < t.num_edges(); ++e) not_delaunay += !is_delaunay(t, state, e);
    const FlipReport report = make_delaunay(t, s, s.u0, state, 100 * t.num_edges(), false);
    EXPECT_GT(report.flips, not_delaunay / 2) << to_string(g);
    expect_valid_triangulation(t);
    // The state the routine kept up to date is the metric of the flipped triangulation.
    const MetricState fresh = evaluate_metric(t, s, s.u0);
    ASSERT_TRUE(fresh.valid());
    for (int e = 0; e < t.num_edges(); ++e) {
      EXPECT_NEAR(fresh.edges[e].length, state.edges[e].length, 1e-12 * state.edges[e].length);
    }
    int left = 0;
    for (int e = 0; e < t.num_edges(); ++e) left += !is_delaunay(t, fresh, e);
    EXPECT_LE(left, report.blocked)
        << to_string(g) << ": every edge is Delaunay unless its flip was blocked";
    EXPECT_LT(left, t.num_edges() / 100);
    // Same metric: every vertex keeps its angle sum, the surface its area.
    EXPECT_LE((curvature(t, fresh) - k_before).cwiseAbs().maxCoeff(), 1e-9) << to_string(g);
    EXPECT_NEAR(total_area(t, g, fresh) / area_before, 1.0, 1e-10);
  }
}

TEST(Delaunay, HyperbolicYamabeIsDelaunayWhereItsChordsAre) {
  // H2 Yamabe flips by Ptolemy's relation on the chords 2 sinh(l/2); that is the metric's own
  // flip only if the chords' Delaunay criterion is the metric's (is_delaunay(), from the Hessian's
  // off-diagonal entries), at every scale of the input lengths.
  for (const char* name : {"eight.off", "femur.off"}) {
    const CompactMesh mesh = test::cgal_mesh(name);
    SchemeOptions options;
    options.scheme = Scheme::Yamabe;
    for (double scale : {0.02, 0.3, 1.0}) {
      const ConformalStructure s = initialize_scheme(mesh, Geometry::Hyperbolic, options, scale);
      ASSERT_TRUE(all_ptolemy(s));
      const IntrinsicTriangulation t(mesh);
      const MetricState state = evaluate_metric(t, s, s.u0);
      ASSERT_TRUE(state.valid());
      int not_delaunay = 0, disagree = 0;
      for (int e = 0; e < t.num_edges(); ++e) {
        const bool by_hessian = is_delaunay(t, state, e, 0);
        not_delaunay += !by_hessian;
        disagree += by_hessian != is_ptolemy_delaunay(t, Geometry::Hyperbolic, state, e, 0);
      }
      EXPECT_GT(not_delaunay, t.num_edges() / 20) << name << " at scale " << scale;
      EXPECT_EQ(disagree, 0) << name << " at scale " << scale;
    }
  }
}

TEST(Delaunay, PtolemyFlipsFromLengthsMakeEveryTriangleValid) {
  // Yamabe on a closed scan, at a conformal factor far from the input's: many triangles violate
  // the triangle inequality; flipping by the lengths alone must end with every triangle valid and
  // every edge Delaunay (E2: Springborn 2020; H2: the same for the chords, delaunay.h). (Steeper
  // factors need Delaunay triangulations with self-loops, which are refused: then triangles can
  // stay invalid.)
  const CompactMesh mesh = test::cgal_mesh("elephant.off");
  SchemeOptions options;
  options.scheme = Scheme::Yamabe;
  Eigen::VectorXd u(mesh.num_vertices());
  // A smooth factor, as the flow's: u = 2 sin(15 x), x across the elephant.
  double lo = 1e300, hi = -1e300;
  for (const auto& p : mesh.positions()) lo = std::min(lo, p.x()), hi = std::max(hi, p.x());
  for (int v = 0; v < u.size(); ++v)
    u[v] = 2 * std::sin(15 * (mesh.positions()[v].x() - lo) / (hi - lo));
  for (Geometry g : {Geometry::Euclidean, Geometry::Hyperbolic}) {
    ConformalStructure s = initialize_scheme(mesh, g, options, 1.0);
    ASSERT_TRUE(all_ptolemy(s));
    IntrinsicTriangulation t(mesh);
    MetricState state = evaluate_metric(t, s, u);
    ASSERT_GE(state.num_invalid_faces, 10) << to_string(g);  // E2: 22
    const FlipReport report = make_delaunay(t, s, u, state, 100 * t.num_edges(), false);
    EXPECT_GT(report.flips, 0);
    EXPECT_EQ(report.blocked, 0);
    expect_valid_triangulation(t);
    const MetricState fresh = evaluate_metric(t, s, u);
    ASSERT_TRUE(fresh.valid()) << to_string(g) << ": " << fresh.num_invalid_faces
                               << " invalid triangles left";
    EXPECT_TRUE(state.valid());
    for (int e = 0; e < t.num_edges(); ++e) {
      EXPECT_TRUE(is_delaunay(t, fresh, e, 1e-8)) << to_string(g) << ", edge " << e;
      EXPECT_NEAR(fresh.edges[e].length, state.edges[e].length, 1e-12 * state.edges[e].length);
    }
  }
  // The packing schemes keep the metric through a flip and cannot flip from lengths alone: an
  // invalid state is left as it is.
  options.scheme = Scheme::Tangential;
  const ConformalStructure yamabe = initialize_scheme(mesh, Geometry::Euclidean, {}, 1.0);
  ConformalStructure tangential = initialize_scheme(mesh, Geometry::Euclidean, options, 1.0);
  EXPECT_FALSE(all_ptolemy(tangential));
  IntrinsicTriangulation t2(mesh);
  MetricState invalid = evaluate_metric(t2, yamabe, u);
  EXPECT_EQ(make_delaunay(t2, tangential, u, invalid, 100, false).flips, 0);
}

TEST(Delaunay, LineSearchFlipsAcrossInvalidTriangles) {
  // From u = 0 towards the factor of the test above, whose curvature on its Delaunay
  // triangulation is the target: the full step leaves triangles of the input's triangulation
  // invalid. With flips the search takes it (on the flipped triangulation, residual 0); without,
  // it halves to where the input's triangles are still valid.
  const CompactMesh mesh = test::cgal_mesh("elephant.off");
  SchemeOptions options;
  options.scheme = Scheme::Yamabe;
  const ConformalStructure s = initialize_scheme(mesh, Geometry::Euclidean, options, 1.0);
  double lo = 1e300, hi = -1e300;
  for (const auto& p : mesh.positions()) lo = std::min(lo, p.x()), hi = std::max(hi, p.x());
  Eigen::VectorXd goal(mesh.num_vertices());
  for (int v = 0; v < goal.size(); ++v)
    goal[v] = 2 * std::sin(15 * (mesh.positions()[v].x() - lo) / (hi - lo));
  goal.array() -= goal[0];  // vertex 0 is pinned against the scaling
  IntrinsicTriangulation flipped(mesh);
  ConformalStructure flipped_structure = s;
  MetricState at_goal = evaluate_metric(flipped, s, goal);
  ASSERT_FALSE(at_goal.valid());
  make_delaunay(flipped, flipped_structure, goal, at_goal, 100 * flipped.num_edges(), false);
  ASSERT_TRUE(at_goal.valid());
  const TargetCurvature target = TargetCurvature::from_values(mesh, curvature(flipped, at_goal));
  const std::vector<int> free_index =
      detail::free_vertex_index(mesh.num_vertices(), Geometry::Euclidean, target);
  Eigen::VectorXd du(mesh.num_vertices() - 1);
  for (int v = 1; v < mesh.num_vertices(); ++v) du[free_index[v]] = goal[v];
  const IntrinsicTriangulation input(mesh);
  const Eigen::VectorXd u0 = Eigen::VectorXd::Zero(mesh.num_vertices());
  const MetricState start = evaluate_metric(input, s, u0);
  const double phi = 0.5 * detail::free_residual(curvature(input, start), target, free_index,
                                                 static_cast<int>(du.size()))
                               .squaredNorm();
  const detail::LineSearch with =
      detail::search_line(input, s, target, free_index, u0, du, phi, 40, true, false);
  ASSERT_TRUE(with.accepted);
  EXPECT_EQ(with.alpha, 1);
  ASSERT_TRUE(with.flipped.has_value());
  EXPECT_GT(with.flips.flips, 0);
  EXPECT_EQ(static_cast<int>(with.flips.sequence.size()), with.flips.flips);
  EXPECT_LE(detail::max_residual(with.k, target), 1e-9);
  const detail::LineSearch without =
      detail::search_line(input, s, target, free_index, u0, du, phi, 40, false, false);
  EXPECT_TRUE(without.blocked_by_validity);
  EXPECT_FALSE(without.flipped.has_value());
  EXPECT_LT(without.alpha, 1);
}

TEST(Delaunay, FlipTwiceRestoresTheTriangulation) {
  const CompactMesh mesh = test::torus(10, 6);
  IntrinsicTriangulation t(mesh);
  for (int e = 0; e < t.num_edges(); e += 7) {
    const auto before = t.edge_vertices(e);
    const auto opposite = t.opposite_vertices(e);
    ASSERT_TRUE(t.flip(e));
    EXPECT_EQ(t.edge_vertices(e)[0], std::min(opposite[0], opposite[1]));
    EXPECT_EQ(t.edge_vertices(e)[1], std::max(opposite[0], opposite[1]));
    expect_valid_triangulation(t);
    ASSERT_TRUE(t.flip(e));
    EXPECT_EQ(t.edge_vertices(e), before);
  }
  expect_valid_triangulation(t);
  const CompactMesh disk = test::bumpy_disk(4);
  IntrinsicTriangulation d(disk);
  for (int e = 0; e < d.num_edges(); ++e) {
    if (d.is_boundary_edge(e)) {
      EXPECT_FALSE(d.flip(e));
    }
  }
}

// A tetrahedron flipped once has two vertices of degree 2. Flipping an edge at one of them makes
// a loop at the vertex opposite it on both sides, and a face whose two sides are one edge (the
// degree-2 vertex's other edge): refused, the triangulation unchanged. Flipping the new edge
// back is no such flip.
TEST(Delaunay, AFlipToAFaceWithOneEdgeOnTwoSidesIsRefused) {
  IntrinsicTriangulation t(
      Triangulation::from_faces(4, {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}}));
  int e01 = -1, e02 = -1;
  for (int e = 0; e < t.num_edges(); ++e) {
    if (t.edge_vertices(e) == std::array<int, 2>{0, 1}) e01 = e;
    if (t.edge_vertices(e) == std::array<int, 2>{0, 2}) e02 = e;
  }
  ASSERT_TRUE(t.flips_to_triangles(e01));
  ASSERT_TRUE(t.flip(e01));  // 0-1 becomes a second edge 2-3
  expect_valid_triangulation(t);
  const auto opposite = t.opposite_vertices(e02);
  EXPECT_EQ(opposite[0], opposite[1]);  // 3 on both sides: the flip would make a loop 3-3
  const std::vector<std::array<int, 3>> before = t.faces();
  EXPECT_FALSE(t.flips_to_triangles(e02));
  EXPECT_FALSE(t.flip(e02));
  EXPECT_EQ(t.faces(), before);
  EXPECT_TRUE(t.flips_to_triangles(e01));
}

// With flips, the Euclidean Yamabe flow's class is that of the input metric's intrinsic Delaunay
// triangulation (Gillespie, Springborn, Crane): the result is Ptolemy-equivalent to it.
TEST(Delaunay, YamabeWithFlipsIsPtolemyConformalToTheInputsDelaunayTriangulation) {
  for (const char* name : {"elk.off", "lion-head.off"}) {
    const CompactMesh mesh = test::cgal_mesh(name);
    SchemeOptions options;
    options.scheme = Scheme::Yamabe;
    FlowOptions always;
    always.edge_flips = EdgeFlips::Always;
    const FlowResult r = compute_ricci_flow(mesh, Geometry::Euclidean, options,
                                            TargetCurvature::free_boundary_or_zero(mesh), always);
    ASSERT_TRUE(r.converged);
    ASSERT_GT(r.num_flips, 100) << name;
    // Replay the flips on the input's lambda-lengths (u = 0: lambda = input length): first the
    // isometric ones that make the input metric intrinsically Delaunay (the new diagonal of the
    // unfolded quadrilateral, by the law of cosines), then Ptolemy's: lambda_kl lambda_ab =
    // lambda_ka lambda_lb + lambda_al lambda_bk.
    IntrinsicTriangulation t(mesh);
    std::vector<double> lambda = mesh.input_lengths();
    bool ptolemy_seen = false;
    int isometric = 0;
    for (const EdgeFlip& flip : r.flip_sequence) {
      const int e = flip.edge;
      const int h = t.edge_halfedge(e), tw = t.twin(h);
      const int f = h / 3, c = h % 3, g = tw / 3, d = tw % 3;
      const double ka = lambda[t.face_edge(f, (c + 2) % 3)],
                   bk = lambda[t.face_edge(f, (c + 1) % 3)];
      const double al = lambda[t.face_edge(g, (d + 1) % 3)],
                   lb = lambda[t.face_edge(g, (d + 2) % 3)];
      const double ab = lambda[e];
      if (flip.isometric) {
        ASSERT_FALSE(ptolemy_seen) << "an isometric flip after the flow's";
        ++isometric;
        auto angle = [](double x, double y, double z) {
          return std::acos((x * x + y * y - z * z) / (2 * x * y));
        };
        const double at_a = angle(ka, ab, bk) + angle(al, ab, lb);
        lambda[e] = std::sqrt(ka * ka + al * al - 2 * ka * al * std::cos(at_a));
      } else {
        ptolemy_seen = true;
        lambda[e] = (ka * lb + al * bk) / ab;
      }
      ASSERT_TRUE(t.flip(e));
    }
    EXPECT_GT(isometric, 0) << name << " is not Delaunay as given";
    const Triangulation& final_t = result_triangulation(mesh, r);
    for (int e = 0; e < t.num_edges(); ++e) {
      ASSERT_EQ(t.edge_vertices(e), final_t.edge_vertices(e));
      // The result's length is the lambda-length scaled by the conformal factors.
      const auto [i, j] = t.edge_vertices(e);
      EXPECT_NEAR(r.edge_lengths[e] / (lambda[e] * std::exp((r.u[i] + r.u[j]) / 2)), 1.0, 1e-9)
          << name << " edge " << e;
    }
    expect_valid_triangulation(final_t);
  }
}

}  // namespace
}  // namespace ricci
