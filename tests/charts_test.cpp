// Charts of a flat metric: developed exactly, one per piece the seams leave, and their insides
// redrawn harmonic where that keeps them embedded and no less conformal.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "ricci/layout/charts.h"
#include "test_meshes.h"

namespace ricci::test {
namespace {

TEST(Charts, EachFacePlacedByItsOwnSidesKeepsASliverWhoseNeighboursSideDiffers) {
  // Two faces on the edge 0-2: a unit right triangle (0, 1, 2) and a sliver (0, 2, 3) whose long
  // side is that edge. The sliver's own side 0-2 is 1e-9 shorter than its other two together;
  // the right triangle's is 1e-8 longer, as pieces drawn one by one disagree by rounding.
  const Triangulation mesh = Triangulation::from_faces(4, {{0, 1, 2}, {0, 2, 3}});
  const double hypotenuse = std::sqrt(2.0), half = hypotenuse / 2 * (1 + 1e-9);
  std::vector<std::array<double, 3>> sides(2);
  std::vector<double> lengths(mesh.num_edges());
  for (int f = 0; f < 2; ++f) {
    for (int c = 0; c < 3; ++c) {
      const auto [a, b] = mesh.edge_vertices(mesh.face_edge(f, c));
      const bool diagonal = std::min(a, b) == 0 && std::max(a, b) == 2;
      const double l =
          f == 0 ? (diagonal ? hypotenuse * (1 + 1e-8) : 1.0) : (diagonal ? hypotenuse : half);
      sides[f][c] = l;
      lengths[mesh.face_edge(f, c)] = l;  // the last face's: the sliver's own
    }
  }
  const std::vector<char> none(mesh.num_edges(), 0);
  const auto sliver_area = [](const Charts& c) {
    const auto& p = c.corners[1];
    return 0.5 * ((p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x());
  };
  const Charts own = lay_out_charts(mesh, sides, none);
  EXPECT_EQ(own.flipped_faces, 0);
  EXPECT_GT(sliver_area(own), 1e-6);  // its own height, about 3e-5
  // One length per edge, the right triangle's diagonal for both: the sliver's sides no longer
  // close and it collapses.
  for (int c = 0; c < 3; ++c) {
    const auto [a, b] = mesh.edge_vertices(mesh.face_edge(0, c));
    if (std::min(a, b) == 0 && std::max(a, b) == 2) lengths[mesh.face_edge(0, c)] = sides[0][c];
  }
  EXPECT_LT(std::abs(sliver_area(lay_out_charts(mesh, lengths, none))), 1e-12);
}

TEST(Charts, ASidePlacedAtTwiceItsOwnLengthOrMoreIsNotHandedOn) {
  // A strip of faces, each sharing a side with the next: that side is 1.95 long in the face before
  // and 0.5 in the face after, as pieces of a needle whose crossings the common subdivision put
  // apart disagree. Each face scaled to its side as placed would grow the strip 3.9 times a face;
  // drawn at their own size where the two differ by more than twice, the faces stay within the
  // strip's own lengths, none turned.
  const int n = 12;
  std::vector<std::array<int, 3>> faces;
  for (int i = 0; i < n; ++i) {
    faces.push_back(i % 2 == 0 ? std::array<int, 3>{i, i + 1, i + 2}
                               : std::array<int, 3>{i + 1, i, i + 2});
  }
  const Triangulation mesh = Triangulation::from_faces(n + 2, faces);
  std::vector<std::array<double, 3>> sides(n);
  double total = 0;
  for (int f = 0; f < n; ++f) {
    for (int c = 0; c < 3; ++c) {
      const auto [a, b] = mesh.edge_vertices(mesh.face_edge(f, c));
      // Face f spans vertices f, f + 1, f + 2: its side f..f+1 is shared with the face before,
      // f+1..f+2 with the face after, f..f+2 is on the border.
      sides[f][c] = a == f && b == f + 1 ? 0.5 : a == f + 1 && b == f + 2 ? 1.95 : 1.5;
      total += sides[f][c];
    }
  }
  const Charts charts = lay_out_charts(mesh, sides, std::vector<char>(mesh.num_edges(), 0));
  ASSERT_EQ(charts.num_charts, 1);
  EXPECT_EQ(charts.flipped_faces, 0);
  double reach = 0;
  for (const auto& t : charts.corners) {
    for (const auto& q : t) reach = std::max(reach, (q - charts.corners[0][0]).norm());
  }
  EXPECT_LT(reach, total);
}

// A grid of unit squares under a line of needle pairs (1 long, 1e-8 wide, back to back across their
// short side), one row of faces above. Breadth first from the grid's middle, the upper needles are
// reached across their short side first: drawn from it, a needle points its far corner in a
// direction off by the rounding of that side's ends over 1e-8, 1e-7 of the long side, which the
// faces drawn from that corner carry on. The development must reach every face across a long side,
// and draw a needle's own small angle to its precision (its height by the cosine law kept only
// 1e-8 of its long side).
TEST(Charts, NeedlesAreDrawnFromTheirLongSides) {
  const int n = 30, rows = 10;
  const double delta = 1e-8;
  std::vector<Eigen::Vector3d> p;
  const auto g = [&](int i, int j) { return i * (rows + 1) + j; };  // (i, j - rows), j = rows: t_i
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= rows; ++j) p.emplace_back(i, j - rows, 0);
  }
  const int first_tp = static_cast<int>(p.size());
  for (int i = 0; i <= n; ++i) p.emplace_back(i + delta, 0, 0);  // t_i's twin, delta to its right
  for (int i = 0; i <= n; ++i) p.emplace_back(i, 1, 0);          // c_i, above
  const auto t = [&](int i) { return g(i, rows); };
  const auto tp = [&](int i) { return first_tp + i; };
  const auto c = [&](int i) { return first_tp + n + 1 + i; };
  std::vector<std::array<int, 3>> faces;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j + 1 < rows; ++j) {
      faces.push_back({g(i, j), g(i + 1, j), g(i + 1, j + 1)});
      faces.push_back({g(i, j), g(i + 1, j + 1), g(i, j + 1)});
    }
  }
  for (int i = 0; i <= n; ++i) {
    const int b = g(i, rows - 1);
    faces.push_back({b, tp(i), t(i)});  // the needles, back to back on t-tp
    faces.push_back({t(i), tp(i), c(i)});
    if (i == n) break;
    faces.push_back({b, g(i + 1, rows - 1), tp(i)});
    faces.push_back({g(i + 1, rows - 1), t(i + 1), tp(i)});
    faces.push_back({tp(i), t(i + 1), c(i + 1)});
    faces.push_back({tp(i), c(i + 1), c(i)});
  }
  const CompactMesh mesh(p, faces);
  const Charts charts =
      lay_out_charts(mesh, mesh.input_lengths(), std::vector<char>(mesh.num_edges(), 0));
  ASSERT_EQ(charts.num_charts, 1);
  EXPECT_EQ(charts.flipped_faces, 0);
  // The chart is the mesh up to a rigid motion: distances from two grid corners kept to rounding.
  std::vector<Eigen::Vector2d> at(p.size());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) at[mesh.face_vertex(f, k)] = charts.corners[f][k];
  }
  double worst = 0;
  for (size_t v = 0; v < p.size(); ++v) {
    for (int ref : {g(0, 0), g(n, 0)}) {
      const double want = (p[v] - p[ref]).norm(), got = (at[v] - at[ref]).norm();
      worst = std::max(worst, std::abs(got - want));
    }
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(Charts, AFlatGridCutAcrossIsTwoExactChartsWithoutOverlap) {
  const CompactMesh grid = square_grid(8);
  // Cut along x = 0.5: the interior edges with both ends there.
  std::vector<char> cut(grid.num_edges(), 0);
  for (int e = 0; e < grid.num_edges(); ++e) {
    const auto [a, b] = grid.edge_vertices(e);
    cut[e] = !grid.is_boundary_edge(e) && std::abs(grid.positions()[a].x() - 0.5) < 1e-12 &&
             std::abs(grid.positions()[b].x() - 0.5) < 1e-12;
  }
  const Charts charts = lay_out_charts(grid, grid.input_lengths(), cut);
  EXPECT_EQ(charts.num_charts, 2);
  EXPECT_LT(charts.max_relative_length_error, 1e-14);
  EXPECT_EQ(charts.flipped_faces, 0);
  EXPECT_TRUE(overlapping_faces(charts).empty());
  for (int f = 0; f < grid.num_faces(); ++f) {
    double x = 0;
    for (int v : grid.faces()[f]) x += grid.positions()[v].x() / 3;
    EXPECT_EQ(charts.chart[f], charts.chart[0] == 0 ? (x < 0.5 ? 0 : 1) : (x < 0.5 ? 1 : 0));
  }
}

// The flat grid cut along x = 0.5 into two charts, developed from its own lengths.
struct CutGrid {
  CompactMesh mesh;
  std::vector<char> cut;
  Charts charts;
};
CutGrid cut_grid(int n) {
  CutGrid g{square_grid(n), {}, {}};
  g.cut.assign(g.mesh.num_edges(), 0);
  for (int e = 0; e < g.mesh.num_edges(); ++e) {
    const auto [a, b] = g.mesh.edge_vertices(e);
    g.cut[e] = !g.mesh.is_boundary_edge(e) && std::abs(g.mesh.positions()[a].x() - 0.5) < 1e-12 &&
               std::abs(g.mesh.positions()[b].x() - 0.5) < 1e-12;
  }
  g.charts = lay_out_charts(g.mesh, g.mesh.input_lengths(), g.cut);
  return g;
}

// Every corner of vertex v (in every chart) moved by d.
void move_vertex(const CutGrid& g, int v, const Eigen::Vector2d& d, Charts& charts) {
  for (int f = 0; f < g.mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      if (g.mesh.faces()[f][c] == v) charts.corners[f][c] += d;
    }
  }
}

// The chart of a face at vertex v (the last such face's; -1 where v is in none).
int chart_at(const CutGrid& g, const Charts& charts, int v) {
  int chart = -1;
  for (int f = 0; f < g.mesh.num_faces(); ++f) {
    for (int w : g.mesh.faces()[f]) chart = w == v ? charts.chart[f] : chart;
  }
  return chart;
}

TEST(Charts, AHarmonicInsideOfAFlatChartIsItsDevelopment) {
  // Developed exactly, each chart is an isometric copy of its half of the grid; its inside moved
  // and then redrawn harmonic goes back there (the cotangent Laplacian is exact on linear maps).
  const CutGrid g = cut_grid(8);
  Charts moved = g.charts;
  int inside = 0;
  for (int v = 0; v < g.mesh.num_vertices(); ++v) {
    const Eigen::Vector3d& p = g.mesh.positions()[v];
    if (g.mesh.is_boundary_vertex(v) || std::abs(p.x() - 0.5) < 1e-12) continue;
    move_vertex(g, v, Eigen::Vector2d(0.02 * std::sin(7.0 * v), 0.02 * std::cos(5.0 * v)), moved);
    ++inside;
  }
  ASSERT_GT(inside, 20);
  const int redrawn = draw_harmonic_insides(g.mesh, g.mesh.positions(), g.cut,
                                            std::vector<char>(moved.num_charts, 1), moved);
  EXPECT_EQ(redrawn, 2);
  double error = 0;
  for (int f = 0; f < g.mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      error = std::max(error, (moved.corners[f][c] - g.charts.corners[f][c]).norm());
    }
  }
  EXPECT_LT(error, 1e-12);
  // Only the charts asked for are redrawn.
  Charts one = g.charts;
  move_vertex(g, 10, Eigen::Vector2d(0.01, 0), one);
  const Charts before = one;
  std::vector<char> which(one.num_charts, 0);
  which[one.chart[0]] = 1;
  draw_harmonic_insides(g.mesh, g.mesh.positions(), g.cut, which, one);
  for (int f = 0; f < g.mesh.num_faces(); ++f) {
    if (one.chart[f] == one.chart[0]) continue;
    for (int c = 0; c < 3; ++c) EXPECT_EQ(one.corners[f][c], before.corners[f][c]);
  }
}

TEST(Charts, AChartWhoseHarmonicInsideWouldTurnKeepsItsDrawing) {
  // A border corner pulled far across its chart: the harmonic inside of that border turns faces
  // over, so the chart stays as it was drawn; the other chart is redrawn.
  const CutGrid g = cut_grid(8);
  Charts pulled = g.charts;
  int corner = -1;  // a vertex on the outer border, not on the cut: (0, 0.5)
  for (int v = 0; v < g.mesh.num_vertices(); ++v) {
    const Eigen::Vector3d& p = g.mesh.positions()[v];
    if (std::abs(p.x()) < 1e-12 && std::abs(p.y() - 0.5) < 1e-12) corner = v;
  }
  ASSERT_GE(corner, 0);
  move_vertex(g, corner, Eigen::Vector2d(3.0, 0.1), pulled);
  const Charts before = pulled;
  const int redrawn = draw_harmonic_insides(g.mesh, g.mesh.positions(), g.cut,
                                            std::vector<char>(pulled.num_charts, 1), pulled);
  EXPECT_EQ(redrawn, 1);
  const int chart = chart_at(g, pulled, corner);
  for (int f = 0; f < g.mesh.num_faces(); ++f) {
    if (pulled.chart[f] != chart) continue;
    for (int c = 0; c < 3; ++c) EXPECT_EQ(pulled.corners[f][c], before.corners[f][c]);
  }
}

TEST(Charts, AChartWithAFaceTurnedOnItsBorderKeepsItsDrawingTheOtherIsRedrawn) {
  // The left chart's corner face at (0, 1) has its three corners on the border: that corner
  // moved past the face's other side turns it over, and no harmonic inside mends it, so
  // the left chart stays as drawn (an inside vertex moved there stays moved); the right chart's
  // moved inside vertex is drawn back where its development puts it.
  const CutGrid g = cut_grid(8);
  const auto vertex_at = [&](double x, double y) {
    for (int v = 0; v < g.mesh.num_vertices(); ++v) {
      const Eigen::Vector3d& p = g.mesh.positions()[v];
      if (std::abs(p.x() - x) < 1e-12 && std::abs(p.y() - y) < 1e-12) return v;
    }
    return -1;
  };
  const int corner = vertex_at(0, 1), left_inside = vertex_at(0.25, 0.5),
            right_inside = vertex_at(0.75, 0.5);
  ASSERT_GE(std::min({corner, left_inside, right_inside}), 0);
  Charts drawn = g.charts;
  move_vertex(g, corner, Eigen::Vector2d(0.175, -0.175), drawn);
  move_vertex(g, left_inside, Eigen::Vector2d(0.02, 0.01), drawn);
  move_vertex(g, right_inside, Eigen::Vector2d(0.02, 0.01), drawn);
  int turned = 0;
  for (const auto& q : drawn.corners) turned += !(signed_area(q) > 0);
  ASSERT_EQ(turned, 1);
  const Charts before = drawn;
  const int redrawn = draw_harmonic_insides(g.mesh, g.mesh.positions(), g.cut,
                                            std::vector<char>(drawn.num_charts, 1), drawn);
  EXPECT_EQ(redrawn, 1);
  const int left = chart_at(g, drawn, corner);
  double right_error = 0;
  for (int f = 0; f < g.mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      if (drawn.chart[f] == left) {
        EXPECT_EQ(drawn.corners[f][c], before.corners[f][c]);
      } else {
        right_error = std::max(right_error, (drawn.corners[f][c] - g.charts.corners[f][c]).norm());
      }
    }
  }
  EXPECT_LT(right_error, 1e-12);
}

TEST(Charts, AScrambledBlockOfTheInsideIsUntangledAsARegion) {
  // Twelve inside vertices of the left chart, each put where another of them was: most faces
  // around them turn over, and a vertex moved alone towards the mean of its neighbours (whose
  // places are scrambled too) cannot undo it. The block with a ring of faces around it, its outer
  // wedges held on a convex square, is a convex combination map: no face turned.
  const CutGrid g = cut_grid(8);
  std::vector<int> block;
  for (int v = 0; v < g.mesh.num_vertices(); ++v) {
    const Eigen::Vector3d& p = g.mesh.positions()[v];
    if (p.x() > 0.1 && p.x() < 0.4 && p.y() > 0.2 && p.y() < 0.7) block.push_back(v);
  }
  ASSERT_EQ(block.size(), 12u);
  std::vector<Eigen::Vector2d> at(g.mesh.num_vertices());
  for (int f = 0; f < g.mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) at[g.mesh.faces()[f][c]] = g.charts.corners[f][c];
  }
  Charts scrambled = g.charts;
  for (size_t i = 0; i < block.size(); ++i) {
    const int to = block[(5 * i + 7) % block.size()];  // 5 is prime to 12: a permutation
    move_vertex(g, block[i], at[to] - at[block[i]], scrambled);
  }
  const auto turned = [&](const Charts& c) {
    return std::count_if(c.corners.begin(), c.corners.end(),
                         [](const auto& t) { return !(signed_area(t) > 0); });
  };
  ASSERT_GE(turned(scrambled), 10);
  const Charts before = scrambled;
  const std::vector<int> moved =
      untangle_turned_faces(g.mesh, g.mesh.positions(), g.cut, scrambled);
  EXPECT_EQ(turned(scrambled), 0);
  EXPECT_FALSE(moved.empty());
  // The other chart and the border stay (the cut at x = 0.5, the boundary).
  for (int f = 0; f < g.mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d& p = g.mesh.positions()[g.mesh.faces()[f][c]];
      if (p.x() > 0.4 || p.x() < 1e-12 || p.y() < 1e-12 || p.y() > 1 - 1e-12) {
        EXPECT_EQ(scrambled.corners[f][c], before.corners[f][c]);
      }
    }
  }
  EXPECT_TRUE(overlapping_faces(g.mesh, g.cut, scrambled).empty());
}

}  // namespace
}  // namespace ricci::test
