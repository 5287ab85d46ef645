// Overlaps within a chart: found anywhere in it (and only real ones), charts embedded for certain
// only where their border is simple, and the sheets of an overlap parted by separate_sheets.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "ricci/layout/charts.h"
#include "test_meshes.h"

namespace ricci::test {
namespace {

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

TEST(ChartOverlaps, OverlapsAreFoundAcrossTheWholeChartAndOnlyWhereTheyAre) {
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

TEST(ChartOverlaps, AChartIsEmbeddedForCertainOnlyWhereItsBorderIsSimple) {
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

TEST(ChartOverlaps, SeparatingTheSheetsLeavesNoOverlap) {
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

TEST(ChartOverlaps, EveryPairPartedInTurnBeforeOneLayoutLeavesNoOverlap) {
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

// A flat strip of 40 x 10 unit squares in the plane, narrowed to its 2 middle rows over the 4
// columns from `neck` on (none where neck < 0): a wide chart with a narrow neck.
CompactMesh necked_strip(int neck) {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; j <= 10; ++j) p.emplace_back(i, j, 0);
  }
  const auto at = [](int i, int j) { return 11 * i + j; };
  std::vector<std::array<int, 3>> f;
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 10; ++j) {
      if (neck >= 0 && i >= neck && i < neck + 4 && (j < 4 || j >= 6)) continue;
      f.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      f.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  // Numbered again over the vertices the faces use.
  std::vector<int> index(p.size(), -1);
  std::vector<Eigen::Vector3d> used;
  for (auto& t : f) {
    for (int& v : t) {
      if (index[v] < 0) index[v] = static_cast<int>(used.size()), used.push_back(p[v]);
      v = index[v];
    }
  }
  return CompactMesh(used, f);
}

// The seam that parts faces at the strip's two ends (the middle rows): its 3D length, and the
// share of the faces on f's side.
struct Parting {
  double length = 0, f_side = 0;
};
Parting parting_seam(const CompactMesh& mesh, bool shortest) {
  std::vector<double> lengths;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [a, b] = mesh.edge_vertices(e);
    lengths.push_back((mesh.positions()[a] - mesh.positions()[b]).norm());
  }
  const std::vector<Eigen::Vector3d> centroid = face_centroids(mesh);
  int f = 0, g = 0;
  for (int h = 0; h < mesh.num_faces(); ++h) {
    if ((centroid[h] - Eigen::Vector3d(0.3, 5.3, 0)).norm() < 0.5) f = h;
    if ((centroid[h] - Eigen::Vector3d(39.7, 5.3, 0)).norm() < 0.5) g = h;
  }
  std::vector<int> part(mesh.num_faces(), 0);
  std::vector<char> cut(mesh.num_edges(), 0);
  const int marked = shortest
                         ? SheetSeparator(mesh, part, lengths).separate(1, f, g, {}, centroid, cut)
                         : separate_sheets(mesh, part, 1, f, g, {}, centroid, cut);
  EXPECT_GT(marked, 0);
  EXPECT_NE(part[f], part[g]);
  Parting p;
  for (int e = 0; e < mesh.num_edges(); ++e) p.length += cut[e] ? lengths[e] : 0;
  // The seam parts the strip in two: each side is connected across uncut edges.
  for (int side : {0, 1}) {
    std::vector<char> seen(mesh.num_faces(), 0);
    std::vector<int> stack{side == part[f] ? f : g};
    seen[stack[0]] = 1;
    int count = 1;
    while (!stack.empty()) {
      const int h = stack.back();
      stack.pop_back();
      for (int c = 0; c < 3; ++c) {
        const int t = mesh.twin(3 * h + c);
        if (t < 0 || cut[mesh.face_edge(h, c)] || seen[t / 3]) continue;
        seen[t / 3] = 1, ++count;
        stack.push_back(t / 3);
      }
    }
    EXPECT_EQ(count, std::count(part.begin(), part.end(), side));
  }
  p.f_side = static_cast<double>(std::count(part.begin(), part.end(), part[f])) / mesh.num_faces();
  return p;
}

TEST(ChartOverlaps, SheetsArePartedAtANeckNearTheMiddleWhereTheSeamIsShortest) {
  // Faces nearer one end than the other part across the strip's full width (10); given the
  // edges' lengths, the separator parts the strip at its neck (2 wide) a third of the way along,
  // within the band of the middle.
  const CompactMesh near_middle = necked_strip(12);
  EXPECT_GE(parting_seam(near_middle, false).length, 10);
  EXPECT_NEAR(parting_seam(near_middle, true).length, 2, 1e-12);
  // A neck at an end, outside the band, is not taken: the strip parts across its width.
  EXPECT_GE(parting_seam(necked_strip(1), true).length, 10);
  // Without a neck the strip parts in its middle, as the nearest share parts it, not where the
  // zigzag of its edges happens to be a little shorter.
  const Parting uniform = parting_seam(necked_strip(-1), true);
  EXPECT_NEAR(uniform.length, parting_seam(necked_strip(-1), false).length, 1e-12);
  EXPECT_NEAR(uniform.f_side, 0.5, 0.05);
}

TEST(ChartOverlaps, GivenLengthsEachFaceKeepsItsOwnShareAtNoDistanceApart) {
  // Two neighbouring faces whose centroids coincide (degenerate pieces, or centroids a caller
  // gives): at no distance apart, each is its own share, and the separator parts them as
  // separate_sheets does.
  const CompactMesh mesh = necked_strip(-1);
  std::vector<double> lengths;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [a, b] = mesh.edge_vertices(e);
    lengths.push_back((mesh.positions()[a] - mesh.positions()[b]).norm());
  }
  std::vector<Eigen::Vector3d> centroid = face_centroids(mesh);
  const int f = 100, g = mesh.twin(3 * f) / 3;
  ASSERT_GE(g, 0);
  centroid[g] = centroid[f];
  for (bool with_lengths : {false, true}) {
    std::vector<int> part(mesh.num_faces(), 0);
    std::vector<char> cut(mesh.num_edges(), 0);
    const int marked =
        with_lengths ? SheetSeparator(mesh, part, lengths).separate(1, f, g, {}, centroid, cut)
                     : separate_sheets(mesh, part, 1, f, g, {}, centroid, cut);
    EXPECT_GT(marked, 0) << with_lengths;
    EXPECT_NE(part[f], part[g]) << with_lengths;
  }
}

TEST(ChartOverlaps, OverlapDepthIsHowFarTwoFacesReachIntoEachOther) {
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

TEST(ChartOverlaps, OverlapsAreFoundBetweenFacesOfAnySize) {
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

TEST(ChartOverlaps, OnlyChartsLaidOutAsBeforeWithoutOverlapCountAsClean) {
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
