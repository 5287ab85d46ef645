// Charts of a flat metric: developed exactly, one per piece the seams leave; overlaps found
// anywhere in a chart (and only real ones); the sheets of an overlap parted by separate_sheets.
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
  int chart = -1;
  for (int f = 0; f < g.mesh.num_faces(); ++f) {
    for (int v : g.mesh.faces()[f]) chart = v == corner ? pulled.chart[f] : chart;
  }
  for (int f = 0; f < g.mesh.num_faces(); ++f) {
    if (pulled.chart[f] != chart) continue;
    for (int c = 0; c < 3; ++c) EXPECT_EQ(pulled.corners[f][c], before.corners[f][c]);
  }
}

// A flat strip of n x 1 squares whose metric wraps round more than a full turn: its lengths are
// those of an annular sector of angle `turn` (radii 1 and 2), so its layout overlaps itself once
// turn > 2 pi.
struct Strip {
  CompactMesh mesh;
  std::vector<double> lengths;
};
// Per face: the centroid of its corners in 3D.
std::vector<Eigen::Vector3d> face_centroids(const CompactMesh& mesh) {
  std::vector<Eigen::Vector3d> centroid;
  for (const auto& t : mesh.faces()) {
    centroid.push_back((mesh.positions()[t[0]] + mesh.positions()[t[1]] + mesh.positions()[t[2]]) /
                       3);
  }
  return centroid;
}

Strip sector_strip(int n, double turn) {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::array<int, 3>> f;
  for (int i = 0; i <= n; ++i) {
    // 3D: a straight strip (the connectivity only); the lengths below are the sector's.
    p.emplace_back(i, 0, 0);
    p.emplace_back(i, 1, 0);
  }
  for (int i = 0; i < n; ++i) {
    f.push_back({2 * i, 2 * i + 2, 2 * i + 3});
    f.push_back({2 * i, 2 * i + 3, 2 * i + 1});
  }
  Strip s{CompactMesh(p, f), {}};
  const auto at = [&](int v) {
    const double r = v % 2 == 0 ? 2 : 1, a = turn * (v / 2) / n;
    return Eigen::Vector2d(r * std::cos(a), r * std::sin(a));
  };
  for (int e = 0; e < s.mesh.num_edges(); ++e) {
    const auto [a, b] = s.mesh.edge_vertices(e);
    s.lengths.push_back((at(a) - at(b)).norm());
  }
  return s;
}

TEST(Charts, OverlapsAreFoundAcrossTheWholeChartAndOnlyWhereTheyAre) {
  const Strip less = sector_strip(60, 1.8 * kPi), more = sector_strip(60, 2.4 * kPi);
  const std::vector<char> none(less.mesh.num_edges(), 0);
  EXPECT_TRUE(overlapping_faces(lay_out_charts(less.mesh, less.lengths, none)).empty());
  const Charts charts = lay_out_charts(more.mesh, more.lengths, none);
  EXPECT_EQ(charts.flipped_faces, 0);
  const auto pairs = overlapping_faces(charts);
  ASSERT_FALSE(pairs.empty());
  // The sheets that overlap are the strip's two ends, a turn apart: faces about 2 * 60 / 2.4 =
  // 50 squares apart.
  for (const auto& [f, g] : pairs) EXPECT_GT(g / 2 - f / 2, 40) << f << " " << g;
}

TEST(Charts, AChartIsEmbeddedForCertainOnlyWhereItsBorderIsSimple) {
  // The strip of 1.8 turns is a disk drawn without overlap: its border is a simple polygon. Of 2.4
  // turns its ends overlap and its border crosses itself; of 2 turns exactly its ends meet, the
  // border touches itself, and the whole test decides.
  for (const double turns : {0.9, 1.2, 1.0}) {
    const Strip strip = sector_strip(60, 2 * turns * kPi);
    const std::vector<char> none(strip.mesh.num_edges(), 0);
    const Charts charts = lay_out_charts(strip.mesh, strip.lengths, none);
    ASSERT_EQ(charts.num_charts, 1);
    const std::vector<char> embedded = embedded_charts(strip.mesh, none, charts);
    EXPECT_EQ(embedded, std::vector<char>{turns < 1}) << turns;
    if (embedded[0]) {
      EXPECT_TRUE(overlapping_faces(charts).empty());
    }
  }
  // The grid cut across: two disks, both embedded. Cut along a slit from its border into its
  // middle: one disk, without overlap, but the slit's two sides lie on one segment, its border
  // touches itself, and the whole test decides.
  const CompactMesh grid = square_grid(8);
  std::vector<char> across(grid.num_edges(), 0), slit(grid.num_edges(), 0);
  for (int e = 0; e < grid.num_edges(); ++e) {
    const auto [a, b] = grid.edge_vertices(e);
    const Eigen::Vector3d &p = grid.positions()[a], &q = grid.positions()[b];
    const bool on_middle = std::abs(p.x() - 0.5) < 1e-12 && std::abs(q.x() - 0.5) < 1e-12;
    across[e] = !grid.is_boundary_edge(e) && on_middle;
    slit[e] = across[e] && std::max(p.y(), q.y()) <= 0.5 + 1e-12;
  }
  EXPECT_EQ(embedded_charts(grid, across, lay_out_charts(grid, grid.input_lengths(), across)),
            (std::vector<char>{1, 1}));
  const Charts slit_open = lay_out_charts(grid, grid.input_lengths(), slit);
  EXPECT_EQ(slit_open.num_charts, 1);
  EXPECT_EQ(embedded_charts(grid, slit, slit_open), std::vector<char>{0});
  EXPECT_TRUE(overlapping_faces(slit_open).empty());
  // Not a disk: the grid's middle square's faces taken out leave an annulus, tested whole.
  std::vector<std::array<int, 3>> ring;
  for (int f = 0; f < grid.num_faces(); ++f) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : grid.faces()[f]) c += grid.positions()[v] / 3;
    if (std::abs(c.x() - 0.5) > 0.25 || std::abs(c.y() - 0.5) > 0.25)
      ring.push_back(grid.faces()[f]);
  }
  std::vector<int> index(grid.num_vertices(), -1);
  int used = 0;
  for (auto& t : ring) {
    for (int& v : t) v = index[v] >= 0 ? index[v] : (index[v] = used++);
  }
  std::vector<Eigen::Vector3d> at(used);
  for (int v = 0; v < grid.num_vertices(); ++v) {
    if (index[v] >= 0) at[index[v]] = grid.positions()[v];
  }
  const Triangulation annulus = Triangulation::from_faces(used, ring);
  std::vector<double> lengths(annulus.num_edges());
  for (int e = 0; e < annulus.num_edges(); ++e) {
    const auto [a, b] = annulus.edge_vertices(e);
    lengths[e] = (at[a] - at[b]).norm();
  }
  const std::vector<char> none(annulus.num_edges(), 0);
  EXPECT_EQ(embedded_charts(annulus, none, lay_out_charts(annulus, lengths, none)),
            std::vector<char>{0});
}

TEST(Charts, SeparatingTheSheetsLeavesNoOverlap) {
  const Strip strip = sector_strip(60, 2.4 * kPi);
  std::vector<char> cut(strip.mesh.num_edges(), 0);
  Charts charts = lay_out_charts(strip.mesh, strip.lengths, cut);
  const auto pairs = overlapping_faces(charts);
  ASSERT_FALSE(pairs.empty());
  const std::vector<Eigen::Vector3d> centroid = face_centroids(strip.mesh);
  std::vector<int> part = charts.chart;
  EXPECT_GT(
      separate_sheets(strip.mesh, part, 1, pairs[0].first, pairs[0].second, {}, centroid, cut), 0);
  EXPECT_NE(part[pairs[0].first], part[pairs[0].second]);
  charts = lay_out_charts(strip.mesh, strip.lengths, cut);
  EXPECT_EQ(charts.num_charts, 2);
  EXPECT_NE(charts.chart[pairs[0].first], charts.chart[pairs[0].second]);
  EXPECT_TRUE(overlapping_faces(charts).empty());
}

TEST(Charts, EveryPairPartedInTurnBeforeOneLayoutLeavesNoOverlap) {
  // A strip of 3.4 turns lies in four sheets. Its pairs parted one after the other, each in the
  // piece it still lies in (as the atlas's split rounds do), and laid out once: the pieces
  // labelled are the charts laid out, and none overlaps.
  const Strip strip = sector_strip(120, 6.8 * kPi);
  std::vector<char> cut(strip.mesh.num_edges(), 0);
  const Charts charts = lay_out_charts(strip.mesh, strip.lengths, cut);
  const auto pairs = overlapping_faces(charts);
  ASSERT_FALSE(pairs.empty());
  const std::vector<Eigen::Vector3d> centroid = face_centroids(strip.mesh);
  ASSERT_EQ(charts.num_charts, 1);
  std::vector<int> part = charts.chart;
  int parts = 1;
  for (const auto& [f, g] : pairs) {
    if (part[f] == part[g]) {
      ASSERT_GT(separate_sheets(strip.mesh, part, parts, f, g, {}, centroid, cut), 0);
      ++parts;
    }
  }
  EXPECT_GE(parts, 4);
  const Charts parted = lay_out_charts(strip.mesh, strip.lengths, cut);
  EXPECT_EQ(parted.num_charts, parts);
  for (size_t f = 0; f < part.size(); ++f) {
    for (size_t h = f + 1; h < part.size(); ++h) {
      EXPECT_EQ(part[f] == part[h], parted.chart[f] == parted.chart[h]) << f << " " << h;
    }
  }
  EXPECT_TRUE(overlapping_faces(parted).empty());
}

TEST(Charts, OverlapDepthIsHowFarTwoFacesReachIntoEachOther) {
  // The unit right triangle and its copy moved by t < 1 along x overlap by (1 - t) / sqrt(2) (in
  // the hypotenuse's direction); over the longest side, sqrt(2).
  for (double t : {0.0, 0.3, 0.9, 1.0, 1.5}) {
    Charts charts;
    const Eigen::Vector2d a(0, 0), b(1, 0), c(0, 1), shift(t, 0);
    charts.corners = {{a, b, c}, {a + shift, b + shift, c + shift}};
    charts.chart = {0, 0};
    charts.num_charts = 1;
    if (t < 1) {
      EXPECT_NEAR(overlap_depth(charts, 0, 1), (1 - t) / 2, 1e-12) << t;
    } else {
      EXPECT_LE(overlap_depth(charts, 0, 1), 0) << t;  // the copy's left side separates them
    }
    EXPECT_EQ(overlapping_faces(charts).size(), t < 1 ? 1u : 0u) << t;
  }
}

TEST(Charts, OverlapsAreFoundBetweenFacesOfAnySize) {
  // One chart: a triangle of size 1e4 and small ones of size 1e-3 on a line across it; only those
  // whose centres lie inside it overlap it (the small ones are disjoint from each other).
  Charts charts;
  charts.corners.push_back(
      {Eigen::Vector2d(0, 0), Eigen::Vector2d(1e4, 0), Eigen::Vector2d(0, 1e4)});
  std::vector<int> inside;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector2d c(-1960.0 + 80.0 * i, 47.0 + 30.0 * i);  // none on an edge
    charts.corners.push_back({c, c + Eigen::Vector2d(1e-3, 0), c + Eigen::Vector2d(0, 1e-3)});
    if (c.x() > 0 && c.x() + c.y() + 2e-3 < 1e4) inside.push_back(i + 1);
  }
  charts.chart.assign(charts.corners.size(), 0);
  charts.num_charts = 1;
  const auto pairs = overlapping_faces(charts);
  ASSERT_EQ(pairs.size(), inside.size());
  ASSERT_GT(inside.size(), 50u);
  for (size_t i = 0; i < pairs.size(); ++i) {
    EXPECT_EQ(pairs[i], std::make_pair(0, inside[i]));
  }
  // Flagged as known to be clean, the chart is not tested.
  EXPECT_TRUE(overlapping_faces(charts, 0, {1}).empty());
}

TEST(Charts, OnlyChartsLaidOutAsBeforeWithoutOverlapCountAsClean) {
  const Strip less = sector_strip(60, 1.8 * kPi), more = sector_strip(60, 2.4 * kPi);
  const std::vector<char> none(less.mesh.num_edges(), 0);
  const Charts flat = lay_out_charts(less.mesh, less.lengths, none);
  EXPECT_EQ(unchanged_clean_charts(flat, flat, {}), std::vector<char>{1});
  Charts charts = lay_out_charts(more.mesh, more.lengths, none);
  const auto pairs = overlapping_faces(charts);
  ASSERT_FALSE(pairs.empty());
  EXPECT_EQ(unchanged_clean_charts(charts, charts, pairs), std::vector<char>{0});
  // Split in two, neither chart is the one before.
  const std::vector<Eigen::Vector3d> centroid = face_centroids(more.mesh);
  std::vector<char> cut = none;
  std::vector<int> part = charts.chart;
  ASSERT_GT(separate_sheets(more.mesh, part, 1, pairs[0].first, pairs[0].second, {}, centroid, cut),
            0);
  const Charts parted = lay_out_charts(more.mesh, more.lengths, cut);
  ASSERT_EQ(parted.num_charts, 2);
  EXPECT_EQ(unchanged_clean_charts(parted, charts, {}), (std::vector<char>{0, 0}));
}

}  // namespace
}  // namespace ricci::test
