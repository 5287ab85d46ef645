// charts_on_input, pieces_closure and partly_cut_charts (pipeline/texture_atlas.h): a common
// subdivision's charts moved onto the user's faces, all or but some cut into their pieces, on a
// square of two faces whose diagonal a new vertex splits into two pieces each; and
// unfolding_cones, on a cube and a flat grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <vector>

#include <Eigen/Core>

#include "pipeline/texture_atlas.h"
#include "ricci/mesh/geometry.h"
#include "ricci/subdivision/subdivided_mesh.h"
#include "test_meshes.h"

namespace ricci::detail {
namespace {

struct Square {
  CompactMesh mesh;
  CommonSubdivision sub;
  Triangulation delivered;
  Charts charts;
  int diagonal = -1;       // the input edge 0-2
  std::vector<int> under;  // input_edge_under
};

// The square (0, 0) .. (1, 1), faces {0, 1, 2} and {0, 2, 3}, and vertex 4 at the diagonal's
// midpoint: pieces {0, 1, 4}, {4, 1, 2} of face 0 and {0, 4, 3}, {4, 2, 3} of face 1, drawn at
// twice the size, moved by (3, 5), all in chart 0.
Square square() {
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  CompactMesh mesh(p, {{0, 1, 2}, {0, 2, 3}});
  int diagonal = -1;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [a, b] = mesh.edge_vertices(e);
    if (a == 0 && b == 2) diagonal = e;
  }
  CommonSubdivision sub;
  sub.num_input_vertices = 4;
  sub.positions = p;
  sub.positions.emplace_back(0.5, 0.5, 0);
  sub.faces = {{0, 1, 4}, {4, 1, 2}, {0, 4, 3}, {4, 2, 3}};
  sub.input_face = {0, 0, 1, 1};
  sub.vertex_input_edge = {diagonal};
  sub.vertex_edge_parameter = {0.5};
  sub.final_face = {0, 0, 1, 1};
  sub.u = Eigen::VectorXd::LinSpaced(5, 0.1, 0.5);
  sub.vertex_input_face = {0, 0, 0, 1, 0};
  sub.vertex_barycentric = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 1}, {0.5, 0, 0.5}};
  Charts charts;
  charts.num_charts = 1;
  charts.chart.assign(4, 0);
  for (const auto& t : sub.faces) {
    std::array<Eigen::Vector2d, 3> q;
    for (int c = 0; c < 3; ++c) q[c] = 2 * sub.positions[t[c]].head<2>() + Eigen::Vector2d(3, 5);
    charts.corners.push_back(q);
  }
  Triangulation delivered = Triangulation::from_faces(5, sub.faces);
  std::vector<int> under = input_edge_under(mesh, delivered, sub);
  return {std::move(mesh),   std::move(sub), std::move(delivered),
          std::move(charts), diagonal,       std::move(under)};
}

// Per delivered edge, 1 on the edges between the listed vertex pairs.
std::vector<char> seam_on(const Triangulation& t, const std::vector<std::array<int, 2>>& pairs) {
  std::vector<char> seam(t.num_edges(), 0);
  for (int e = 0; e < t.num_edges(); ++e) {
    for (const auto& [a, b] : pairs) {
      const auto ends = t.edge_vertices(e);
      if ((ends[0] == a && ends[1] == b) || (ends[0] == b && ends[1] == a)) seam[e] = 1;
    }
  }
  return seam;
}

TEST(ChartsOnInput, EachDeliveredEdgeKnowsTheInputEdgeUnderIt) {
  const Square s = square();
  ASSERT_GE(s.diagonal, 0);
  ASSERT_EQ(s.under.size(), static_cast<size_t>(s.delivered.num_edges()));
  for (int e = 0; e < s.delivered.num_edges(); ++e) {
    const auto [a, b] = s.delivered.edge_vertices(e);
    if (a == 4 || b == 4) {
      // From the diagonal's midpoint: on the diagonal towards 0 and 2, across the faces to 1, 3.
      const int other = a == 4 ? b : a;
      EXPECT_EQ(s.under[e], other == 0 || other == 2 ? s.diagonal : -1) << a << "-" << b;
    } else {
      // Between two input vertices: the input edge itself.
      ASSERT_GE(s.under[e], 0) << a << "-" << b;
      const auto ends = s.mesh.edge_vertices(s.under[e]);
      EXPECT_EQ(std::min(ends[0], ends[1]), std::min(a, b));
      EXPECT_EQ(std::max(ends[0], ends[1]), std::max(a, b));
    }
  }
}

TEST(ChartsOnInput, EachInputFaceTakesItsPiecesChartAndCorners) {
  const Square s = square();
  ASSERT_GE(s.diagonal, 0);
  const auto in =
      charts_on_input(s.mesh, s.sub, s.delivered, s.under, seam_on(s.delivered, {}), s.charts);
  ASSERT_TRUE(in.has_value());
  EXPECT_EQ(in->charts.num_charts, 1);
  EXPECT_EQ(in->charts.chart, (std::vector<int>{0, 0}));
  EXPECT_EQ(in->seam, std::vector<char>(s.mesh.num_edges(), 0));
  for (int f = 0; f < 2; ++f) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d p = s.mesh.positions()[s.mesh.faces()[f][c]];
      EXPECT_EQ(in->charts.corners[f][c], 2 * p.head<2>() + Eigen::Vector2d(3, 5));
    }
  }
}

TEST(ChartsOnInput, ASeamAlongAWholeInputEdgeIsThatEdge) {
  Square s = square();
  s.charts.num_charts = 2;
  s.charts.chart = {0, 0, 1, 1};
  const auto in = charts_on_input(s.mesh, s.sub, s.delivered, s.under,
                                  seam_on(s.delivered, {{0, 4}, {4, 2}}), s.charts);
  ASSERT_TRUE(in.has_value());
  EXPECT_EQ(in->charts.chart, (std::vector<int>{0, 1}));
  for (int e = 0; e < s.mesh.num_edges(); ++e) EXPECT_EQ(in->seam[e], e == s.diagonal) << e;
}

TEST(ChartsOnInput, NoneWhereTheSeamsOrChartsDoNotFollowTheInputsFaces) {
  Square s = square();
  // A seam along half of the diagonal only.
  EXPECT_FALSE(charts_on_input(s.mesh, s.sub, s.delivered, s.under, seam_on(s.delivered, {{0, 4}}),
                               s.charts));
  // A seam inside input face 0 (from its corner 1 to the diagonal's midpoint).
  EXPECT_FALSE(charts_on_input(s.mesh, s.sub, s.delivered, s.under, seam_on(s.delivered, {{1, 4}}),
                               s.charts));
  // The pieces of input face 0 in two charts.
  Charts split = s.charts;
  split.num_charts = 2;
  split.chart = {0, 1, 1, 1};
  EXPECT_FALSE(
      charts_on_input(s.mesh, s.sub, s.delivered, s.under, seam_on(s.delivered, {}), split));
  // Another mesh's subdivision.
  s.sub.num_input_vertices = 3;
  EXPECT_FALSE(
      charts_on_input(s.mesh, s.sub, s.delivered, s.under, seam_on(s.delivered, {}), s.charts));
}

TEST(PartlyCut, TheClosureCrossesTheInputEdgesThatANewVertexSplits) {
  Square s = square();
  // The diagonal is split at vertex 4: face 0 takes face 1 along.
  EXPECT_EQ(pieces_closure(s.mesh, s.under, {0}), (std::vector<char>{1, 1}));
  EXPECT_EQ(pieces_closure(s.mesh, s.under, {}), (std::vector<char>{0, 0}));
  // Were the diagonal one delivered edge (the other half taken for no input edge's), it stops.
  bool first = true;
  for (int& e : s.under) {
    if (e != s.diagonal) continue;
    if (!first) e = -1;
    first = false;
  }
  EXPECT_EQ(pieces_closure(s.mesh, s.under, {0}), (std::vector<char>{1, 0}));
}

TEST(PartlyCut, CutFacesComeAsTheirPiecesAndTheOthersAsTheUsers) {
  const Square s = square();
  const std::vector<char> seam = seam_on(s.delivered, {{0, 4}, {4, 2}});
  Charts charts = s.charts;
  charts.num_charts = 2;
  charts.chart = {0, 0, 1, 1};
  const auto in = charts_on_input(s.mesh, s.sub, s.delivered, s.under, seam, charts);
  ASSERT_TRUE(in.has_value());
  // Neither cut: the user's two faces, their corners where the pieces put them, the diagonal a
  // seam, no new vertex.
  const PartlyCutCharts none =
      partly_cut_charts(s.mesh, s.sub, s.delivered, seam, charts, *in, {0, 0});
  EXPECT_EQ(none.input_faces_cut, 0);
  EXPECT_EQ(none.sub.faces, s.mesh.faces());
  EXPECT_EQ(none.sub.positions.size(), 4u);
  EXPECT_EQ(none.sub.input_face, (std::vector<int>{0, 1}));
  EXPECT_EQ(none.charts.chart, (std::vector<int>{0, 1}));
  EXPECT_EQ(none.charts.corners, in->charts.corners);
  const Triangulation& two = none.delivered;
  ASSERT_EQ(none.seam.size(), static_cast<size_t>(two.num_edges()));
  for (int e = 0; e < two.num_edges(); ++e) {
    const auto [a, b] = two.edge_vertices(e);
    EXPECT_EQ(none.seam[e], a == 0 && b == 2) << a << "-" << b;
  }
  // Both cut: the four pieces with the new vertex and its data, the two halves of the diagonal
  // seams.
  const PartlyCutCharts both =
      partly_cut_charts(s.mesh, s.sub, s.delivered, seam, charts, *in, {1, 1});
  EXPECT_EQ(both.input_faces_cut, 2);
  EXPECT_EQ(both.sub.faces, s.sub.faces);
  EXPECT_EQ(both.sub.positions, s.sub.positions);
  EXPECT_EQ(both.sub.u, s.sub.u);
  EXPECT_EQ(both.sub.vertex_input_edge, s.sub.vertex_input_edge);
  EXPECT_EQ(both.sub.vertex_barycentric, s.sub.vertex_barycentric);
  EXPECT_EQ(both.sub.input_face, s.sub.input_face);
  EXPECT_EQ(both.charts.corners, charts.corners);
  EXPECT_EQ(both.seam, seam);
}

TEST(PartlyCut, ACutFacesPiecesTakeItsPlaceBesideTheUsersFaces) {
  // The square with a third face {1, 5, 2} on its right, one piece of its own, across the whole
  // input edge 1-2, a seam: faces 0 and 1 cut (across the split diagonal), face 2 not.
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}};
  CompactMesh mesh(p, {{0, 1, 2}, {0, 2, 3}, {1, 4, 2}});
  CommonSubdivision sub;
  sub.num_input_vertices = 5;
  sub.positions = p;
  sub.positions.emplace_back(0.5, 0.5, 0);
  sub.faces = {{0, 1, 5}, {5, 1, 2}, {0, 5, 3}, {5, 2, 3}, {2, 1, 4}};
  sub.input_face = {0, 0, 1, 1, 2};
  sub.final_face = {0, 0, 1, 1, 2};
  sub.u = Eigen::VectorXd::LinSpaced(6, 0.1, 0.6);
  sub.vertex_input_face = {0, 0, 0, 1, 2, 0};
  sub.vertex_barycentric.assign(6, Eigen::Vector3d(1, 0, 0));
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (mesh.edge_vertices(e) == std::array<int, 2>{0, 2}) sub.vertex_input_edge = {e};
  }
  sub.vertex_edge_parameter = {0.5};
  const Triangulation delivered = Triangulation::from_faces(6, sub.faces);
  const std::vector<int> under = input_edge_under(mesh, delivered, sub);
  Charts charts;
  charts.num_charts = 2;
  charts.chart = {0, 0, 0, 0, 1};
  for (const auto& t : sub.faces) {
    std::array<Eigen::Vector2d, 3> q;
    for (int c = 0; c < 3; ++c) q[c] = 2 * sub.positions[t[c]].head<2>();
    charts.corners.push_back(q);
  }
  const std::vector<char> seam = seam_on(delivered, {{1, 2}});
  const auto in = charts_on_input(mesh, sub, delivered, under, seam, charts);
  ASSERT_TRUE(in.has_value());
  const std::vector<char> cut_up = pieces_closure(mesh, under, {0});
  EXPECT_EQ(cut_up, (std::vector<char>{1, 1, 0}));
  const PartlyCutCharts partly = partly_cut_charts(mesh, sub, delivered, seam, charts, *in, cut_up);
  EXPECT_EQ(partly.input_faces_cut, 2);
  // In the input's order, a cut face's pieces in its place; face 2 as the input lists it, its
  // corners turned to that order.
  EXPECT_EQ(partly.sub.faces, (std::vector<std::array<int, 3>>{
                                  {0, 1, 5}, {5, 1, 2}, {0, 5, 3}, {5, 2, 3}, {1, 4, 2}}));
  EXPECT_EQ(partly.sub.input_face, (std::vector<int>{0, 0, 1, 1, 2}));
  EXPECT_EQ(partly.charts.chart, (std::vector<int>{0, 0, 0, 0, 1}));
  for (size_t f = 0; f < partly.sub.faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(partly.charts.corners[f][c], 2 * sub.positions[partly.sub.faces[f][c]].head<2>())
          << f << " " << c;
    }
  }
  // The seam on edge 1-2 alone, from both its faces.
  const Triangulation& t = partly.delivered;
  for (int e = 0; e < t.num_edges(); ++e) {
    EXPECT_EQ(partly.seam[e], t.edge_vertices(e) == (std::array<int, 2>{1, 2})) << e;
  }
}

TEST(UnfoldingCones, ACubeHasItsEightCornersAtThreeQuarterTurnsAFlatGridNone) {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 8; ++i) p.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const CompactMesh cube(p, {{0, 2, 1},
                             {1, 2, 3},
                             {4, 5, 6},
                             {5, 7, 6},
                             {0, 1, 4},
                             {1, 5, 4},
                             {2, 6, 3},
                             {3, 6, 7},
                             {0, 4, 2},
                             {2, 4, 6},
                             {1, 3, 5},
                             {3, 7, 5}});
  const ConePlacement c = unfolding_cones(cube, 1e-10);
  ASSERT_EQ(c.cones.size(), 8u);
  for (const Cone& cone : c.cones) EXPECT_NEAR(cone.angle, 1.5 * kPi, 1e-12);
  EXPECT_EQ(c.u.size(), 8);
  EXPECT_EQ(c.u.cwiseAbs().maxCoeff(), 0);
  EXPECT_TRUE(c.bound_reached);
  // A flat square grid: its interior vertices are flat, its boundary is free.
  EXPECT_TRUE(unfolding_cones(ricci::test::square_grid(6), 1e-10).cones.empty());
}

}  // namespace
}  // namespace ricci::detail
