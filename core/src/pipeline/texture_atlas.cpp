#include "pipeline/texture_atlas.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <future>
#include <limits>
#include <optional>
#include <sstream>
#include <system_error>
#include <utility>

#include "mesh/clock.h"
#include "ricci/layout/charts.h"
#include "ricci/layout/packing.h"
#include "ricci/layout/seams.h"
#include "ricci/mesh/errors.h"
#include "ricci/mesh/geometry.h"
#include "ricci/subdivision/common_subdivision.h"

namespace ricci::detail {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Rounds of splits of overlapping charts (each parts every overlapping chart at least once).
constexpr int kMaxSplitRounds = 64;
// A round's test of a chart stops once its faces in order make this many overlapping pairs; the
// pairs past them wait for the next round's test. A chart whose sheets overlap in hundreds of
// thousands of pairs is split over the rounds all the same, and its tests cost less
// (gymnasium's Adroit shoulder: a part of 323,769 pieces, 503,816 pairs in its first test; its
// charts' stage 9.2 s to 6.5 s in one run each, the same atlas).
constexpr size_t kPairsPerChart = 4096;
// Within a round, further pairs of a chart are parted while they overlap by more than this share
// of the smaller face's longest side (overlap_depth): past what pieces drawn one by one disagree
// by. On 39 atlases of 22 meshes 36 get the charts that one pair a chart a round gives; with a
// quarter instead of a hundredth, the genus-22 part at 8 cones took 16 rounds instead of 2.
constexpr double kDeepOverlap = 0.01;
// Charts longer than this times their width are halved, at most this many rounds.
constexpr double kLongAspect = 2;
constexpr int kMaxHalvings = 4;

// Every face of the flowed triangulation drawn alone by its side lengths: all the common
// subdivision needs of a layout is each face's corners.
Layout faces_drawn_alone(const Triangulation& flowed, const std::vector<double>& lengths) {
  Layout layout;
  layout.geometry = Geometry::Euclidean;
  layout.corners.resize(flowed.num_faces());
  for (int f = 0; f < flowed.num_faces(); ++f) {
    const double a = lengths[flowed.face_edge(f, 0)], b = lengths[flowed.face_edge(f, 1)],
                 c = lengths[flowed.face_edge(f, 2)];
    const auto [x, y] = triangle_apex(c, b, a);
    layout.corners[f] = {Eigen::Vector3d::Zero(), Eigen::Vector3d(c, 0, 0),
                         Eigen::Vector3d(x, y, 0)};
  }
  return layout;
}

// Per chart longer than `aspect` times its width (by the second moments of its corners), its
// faces farthest apart along its long axis.
std::vector<std::pair<int, int>> long_chart_ends(const Charts& charts, double aspect) {
  const int nf = static_cast<int>(charts.corners.size());
  std::vector<Eigen::Vector2d> mean(charts.num_charts, Eigen::Vector2d::Zero());
  std::vector<Eigen::Matrix2d> moment(charts.num_charts, Eigen::Matrix2d::Zero());
  std::vector<int> count(charts.num_charts, 0);
  for (int f = 0; f < nf; ++f) {
    for (const auto& q : charts.corners[f]) mean[charts.chart[f]] += q, ++count[charts.chart[f]];
  }
  for (int k = 0; k < charts.num_charts; ++k) mean[k] /= std::max(count[k], 1);
  for (int f = 0; f < nf; ++f) {
    for (const auto& q : charts.corners[f]) {
      const Eigen::Vector2d d = q - mean[charts.chart[f]];
      moment[charts.chart[f]] += d * d.transpose();
    }
  }
  std::vector<std::pair<int, int>> ends;
  std::vector<Eigen::Vector2d> axis(charts.num_charts, Eigen::Vector2d::Zero());
  for (int k = 0; k < charts.num_charts; ++k) {
    // The symmetric 2 x 2 moment's eigenvalues and its major axis, in closed form.
    const double a = moment[k](0, 0), b = moment[k](0, 1), c = moment[k](1, 1);
    const double mid = (a + c) / 2, radius = std::sqrt((a - c) * (a - c) / 4 + b * b);
    const double major = mid + radius, minor = mid - radius;
    if (!(major > aspect * aspect * std::max(minor, 0.0))) continue;
    const Eigen::Vector2d d =
        a >= c ? Eigen::Vector2d(major - c, b) : Eigen::Vector2d(b, major - a);
    axis[k] = d.normalized();
  }
  std::vector<int> lo(charts.num_charts, -1), hi(charts.num_charts, -1);
  std::vector<double> lo_at(charts.num_charts, INFINITY), hi_at(charts.num_charts, -INFINITY);
  for (int f = 0; f < nf; ++f) {
    const int k = charts.chart[f];
    if (axis[k].isZero()) continue;
    const double t =
        axis[k].dot((charts.corners[f][0] + charts.corners[f][1] + charts.corners[f][2]) / 3);
    if (t < lo_at[k]) lo_at[k] = t, lo[k] = f;
    if (t > hi_at[k]) hi_at[k] = t, hi[k] = f;
  }
  for (int k = 0; k < charts.num_charts; ++k) {
    if (lo[k] >= 0 && hi[k] >= 0 && lo[k] != hi[k]) ends.emplace_back(lo[k], hi[k]);
  }
  return ends;
}

std::vector<std::vector<std::array<Eigen::Vector2d, 3>>> triangles_by_chart(const Charts& charts) {
  std::vector<std::vector<std::array<Eigen::Vector2d, 3>>> by_chart(charts.num_charts);
  for (size_t f = 0; f < charts.corners.size(); ++f) {
    by_chart[charts.chart[f]].push_back(charts.corners[f]);
  }
  return by_chart;
}

// Seconds since `from`, and `from` moved to now.
double lap(Clock::time_point& from) {
  const Clock::time_point now = Clock::now();
  const double s = std::chrono::duration<double>(now - from).count();
  from = now;
  return s;
}

// The widest wedge that the seams leave a cone (ConeWedges): a full turn, past which a wedge
// overlaps itself at the cone's vertex. Before, a cone of angle theta had floor(theta / 2 pi) + 1
// branches, each the shortest path to the cut, which can leave one wedge past a full turn: CGAL's
// man at 8 cones, a cone of 10.87 in wedges of 2.86, 1.58 and 6.42, its chart split 5 times; the
// camel's cone of 14.74 in 1.62, 10.90 and 2.22. (At most 1.9 pi, the cones of an unfolded CAD
// part just below a full turn took a branch each: Cura's felixpro2 bed 80 charts instead of 15.)
constexpr double kWidestWedge = 2 * kPi;

// A cone's further branch ends on the cut at least this many times sqrt(area) from the cone along
// it (ConeWedges::branch_end). Ended at the nearest cut vertex, two cut edges along, it closed a
// loop around a few faces by the cone (measured with wedges of at most 1.9 pi): a chart of 2 faces
// below a texel on CGAL's diplodocus at 8 cones, and about man's cone of 1.7 turns loops that left
// its chart overlapping (3 splits, 5 charts); 10 cut edges away (0.07 to 0.11 sqrt(area) on those
// meshes of 20k to 48k faces): no split, 2 charts, neither below a texel. Counted in edges, a
// coarse part's branches ran far (meshcat's head, 686 faces: the seams of its 64 cones 7.07
// sqrt(area) instead of 5.3, so that the QC retry's atlas was not delivered, QC p95 1.51 for
// 1.26; oblong.off no longer unfolded), which this length does not. On the 234 files of the real
// set and CGAL's at the defaults, with the rest of the rule: charts below a texel 16 to 3, overlap
// splits 936 to 407 (docs/atlas-measurements.md).
constexpr double kBranchEnd = 0.1;

// Per face, its side lengths as `corners` draw it (`[f][c]`: the side opposite corner c).
std::vector<std::array<double, 3>> drawn_sides(
    const std::vector<std::array<Eigen::Vector3d, 3>>& corners) {
  std::vector<std::array<double, 3>> sides(corners.size());
  for (size_t f = 0; f < corners.size(); ++f) {
    for (int c = 0; c < 3; ++c)
      sides[f][c] = (corners[f][(c + 1) % 3] - corners[f][(c + 2) % 3]).norm();
  }
  return sides;
}

// Fills run's layout and atlas from the delivered mesh's charts and seams (not yet packed).
void deliver(const Triangulation& delivered, const std::vector<Eigen::Vector3d>& positions,
             const std::vector<std::array<int, 3>>& faces, const std::vector<char>& seam,
             const std::vector<double>& length3d, const Charts& charts,
             const std::vector<std::pair<int, int>>& overlaps, double input_area,
             bool quarter_turns, Uniformization& run) {
  AtlasResult& atlas = run.atlas;
  std::vector<char> overlapping(delivered.num_faces(), 0);
  for (const auto& [f, g] : overlaps) overlapping[f] = overlapping[g] = 1;
  atlas.num_charts = charts.num_charts;
  double seam_length = 0;
  for (int e = 0; e < delivered.num_edges(); ++e) seam_length += seam[e] ? length3d[e] : 0;
  atlas.seam_length = seam_length / std::sqrt(input_area);
  atlas.seam_edges = static_cast<int>(std::count(seam.begin(), seam.end(), 1));
  atlas.overlapping_faces = static_cast<int>(std::count(overlapping.begin(), overlapping.end(), 1));
  std::vector<std::array<Eigen::Vector2d, 3>> corners = charts.corners;
  if (quarter_turns) {
    Charts turned{std::move(corners), charts.chart, charts.num_charts};
    turn_charts_to_quarter_turns(faces, turned);
    corners = std::move(turned.corners);
  }
  run.corners.resize(delivered.num_faces());
  for (int f = 0; f < delivered.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      run.corners[f][c] = Eigen::Vector3d(corners[f][c].x(), corners[f][c].y(), 0);
    }
  }
  run.face_chart = charts.chart;
  atlas.distortion = face_distortion(positions, faces, charts.corners);
  run.layout = Layout();
  run.layout.geometry = Geometry::Euclidean;
  run.layout.corners = run.corners;
  run.layout.max_relative_length_error = charts.max_relative_length_error;
  run.layout.num_flipped_faces = charts.flipped_faces;
}

}  // namespace

std::vector<int> input_edge_under(const CompactMesh& mesh, const Triangulation& delivered,
                                  const CommonSubdivision& sub) {
  std::vector<std::vector<int>> input_edges(delivered.num_vertices());
  for (int e = 0; e < mesh.num_edges(); ++e) {
    for (int v : mesh.edge_vertices(e)) input_edges[v].push_back(e);
  }
  for (int v = mesh.num_vertices(); v < delivered.num_vertices(); ++v) {
    const int e = sub.vertex_input_edge[v - mesh.num_vertices()];
    if (e >= 0) input_edges[v].push_back(e);
  }
  for (auto& list : input_edges) std::sort(list.begin(), list.end());
  std::vector<int> under(delivered.num_edges(), -1);
  for (int e = 0; e < delivered.num_edges(); ++e) {
    const auto [a, b] = delivered.edge_vertices(e);
    const auto& x = input_edges[a];
    const auto& y = input_edges[b];
    size_t i = 0, j = 0;
    while (i < x.size() && j < y.size() && under[e] < 0) {
      if (x[i] == y[j]) {
        under[e] = x[i];
      } else if (x[i] < y[j]) {
        ++i;
      } else {
        ++j;
      }
    }
  }
  return under;
}

std::vector<char> on_input_edges(const std::vector<int>& under) {
  std::vector<char> on(under.size());
  for (size_t e = 0; e < under.size(); ++e) on[e] = under[e] >= 0;
  return on;
}

std::vector<char> on_input_edges(const CompactMesh& mesh, const Triangulation& delivered,
                                 const CommonSubdivision& sub) {
  return on_input_edges(input_edge_under(mesh, delivered, sub));
}

std::vector<double> lengths_in_3d(const Triangulation& delivered,
                                  const std::vector<Eigen::Vector3d>& positions) {
  std::vector<double> length(delivered.num_edges());
  for (int e = 0; e < delivered.num_edges(); ++e) {
    const auto [a, b] = delivered.edge_vertices(e);
    length[e] = (positions[a] - positions[b]).norm();
  }
  return length;
}

double face_distortion(const std::vector<Eigen::Vector3d>& positions,
                       const std::vector<std::array<int, 3>>& faces,
                       const std::vector<std::array<Eigen::Vector2d, 3>>& corners) {
  std::vector<double> area3d(faces.size()), area2d(faces.size());
  double total3d = 0, total2d = 0;
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto& [a, b, c] = faces[f];
    area3d[f] = 0.5 * (positions[b] - positions[a]).cross(positions[c] - positions[a]).norm();
    const Eigen::Vector2d u = corners[f][1] - corners[f][0], v = corners[f][2] - corners[f][0];
    area2d[f] = 0.5 * (u.x() * v.y() - u.y() * v.x());
    if (!(area3d[f] > 0) || !(area2d[f] > 0)) area3d[f] = area2d[f] = 0;  // no weight
    total3d += area3d[f], total2d += area2d[f];
  }
  std::vector<double> s(faces.size(), 0.0);
  double mean = 0;
  for (size_t f = 0; f < faces.size(); ++f) {
    if (area3d[f] == 0) continue;
    s[f] = 0.5 * std::log((area2d[f] / total2d) / (area3d[f] / total3d));
    mean += area3d[f] / total3d * s[f];
  }
  double d = 0;
  for (size_t f = 0; f < faces.size(); ++f)
    d += area3d[f] / total3d * (s[f] - mean) * (s[f] - mean);
  return std::sqrt(d);
}

TargetCurvature atlas_target(const CompactMesh& mesh, const ConePlacement& placement,
                             bool curvatures) {
  curvatures = curvatures || placement.least_distortion;
  Eigen::VectorXd values = Eigen::VectorXd::Zero(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.is_boundary_vertex(v)) values[v] = kNaN;
  }
  for (const Cone& c : placement.cones) values[c.vertex] = curvatures ? 2 * kPi - c.angle : kNaN;
  return TargetCurvature::from_values(mesh, values);
}

ConePlacement unfolding_cones(const CompactMesh& mesh, double flat) {
  std::vector<double> angle_sum(static_cast<size_t>(mesh.num_vertices()), 0.0);
  const std::vector<double>& l = mesh.input_lengths();
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const std::array<int, 3>& e = mesh.face_edges(f);
    const TriangleAngles a = corner_angles(Geometry::Euclidean, {l[e[0]], l[e[1]], l[e[2]]});
    for (int c = 0; c < 3; ++c)
      angle_sum[static_cast<size_t>(mesh.face_vertex(f, c))] += a.angle[c];
  }
  ConePlacement p;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double theta = angle_sum[static_cast<size_t>(v)];
    if (!mesh.is_boundary_vertex(v) && std::abs(theta - 2 * kPi) > flat)
      p.cones.push_back({v, theta});
  }
  p.u = Eigen::VectorXd::Zero(mesh.num_vertices());
  p.distortion = p.max_deviation = 0;
  p.distortion_without_cones = kNaN;
  p.bound_reached = true;
  return p;
}

void lay_out_atlas(const CompactMesh& mesh, const UniformizationOptions& o, Uniformization& run) {
  run.layout_kind = LayoutKind::Atlas;
  // The flow on the surface doubled along its boundary delivers the half's pieces, laid out.
  std::optional<CommonSubdivision> sub;
  if (run.doubled) sub = std::move(run.subdivision);
  run.subdivision.reset();
  run.subdivision_failure.clear();
  run.face_chart.clear();
  run.corners.clear();
  const std::vector<double>& lengths = run.result.edge_lengths;
  AtlasResult& atlas = run.atlas;
  atlas.texture.clear();  // packed by pack_atlas, if at all
  atlas.utilization = atlas.padding = atlas.padding_asked = kNaN;
  atlas.quarter_turns = o.cone_placement.quarter_angles && !atlas.user_cones;
  const bool quarter = atlas.quarter_turns;
  PackingOptions packing_options = o.packing;
  packing_options.quarter_turns_only = quarter;
  atlas.on_input_faces = false;
  atlas.untangled = 0;
  atlas.input_faces_cut = 0;
  atlas.flow_distortion = area_distortion(mesh, run.result.u);
  atlas.cone_angles.clear();
  std::vector<int> cones;
  // On a closed surface the cones' angles as the flow left them, with the curvature that the
  // other vertices keep within the tolerance shared out among the cones: so they satisfy
  // Gauss-Bonnet exactly, and given back as the user's cones they are a valid target (the flow
  // in the canonical class stops at a residual of 7e-11 on CGAL's knot1.off, whose 6,400
  // vertices then kept 1.3e-9 in all).
  double kept_elsewhere = 0;
  if (mesh.is_closed() && !atlas.placement.cones.empty()) {
    std::vector<char> cone(mesh.num_vertices(), 0);
    for (const Cone& c : atlas.placement.cones) cone[c.vertex] = 1;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (!cone[v]) kept_elsewhere += run.result.curvature[v];
    }
    kept_elsewhere /= static_cast<double>(atlas.placement.cones.size());
  }
  for (const Cone& c : atlas.placement.cones) {
    const double theta = (mesh.is_boundary_vertex(c.vertex) ? kPi : 2 * kPi) -
                         run.result.curvature[c.vertex] - kept_elsewhere;
    atlas.cone_angles.push_back(theta);
    cones.push_back(c.vertex);
  }

  // === The delivered mesh, its edges' 3D and flat lengths, and which lie on the user's edges
  if (!sub && !run.result.flip_sequence.empty()) {
    try {
      const Triangulation& flowed = result_triangulation(mesh, run.result);
      // Roundest: the charts' insides are drawn again, harmonic (below).
      sub = common_subdivision(mesh, run.structure, run.result, faces_drawn_alone(flowed, lengths),
                               DiskSidePoints::OnGeodesic, PieceTriangles::Roundest);
    } catch (const LayoutError& e) {
      run.subdivision_failure = e.what();
      return;
    }
    const auto pieces = static_cast<std::int64_t>(sub->faces.size());
    if (o.max_pieces_per_face > 0 &&
        pieces > static_cast<std::int64_t>(o.max_pieces_per_face) * mesh.num_faces()) {
      std::ostringstream why;
      why.precision(3);
      why << "its " << pieces << " pieces, " << static_cast<double>(pieces) / mesh.num_faces()
          << " per input face, are more than the " << o.max_pieces_per_face
          << " this attempt may take";
      run.subdivision_failure = why.str();
      return;
    }
  }
  const std::vector<std::array<int, 3>>& faces = sub ? sub->faces : mesh.faces();
  const std::vector<Eigen::Vector3d>& positions = sub ? sub->positions : mesh.positions();
  std::optional<Triangulation> delivered_mesh;
  try {
    delivered_mesh.emplace(Triangulation::from_faces(static_cast<int>(positions.size()), faces));
  } catch (const InvalidMeshError& e) {
    // Pieces that meet at a vertex in several fans (robosuite's Baxter torso and forearm meshes:
    // 25 input vertices of a part whose flow flipped edges): no atlas of these cones, and the run
    // goes on to the next attempt instead of stopping the whole mesh. The fact, without the
    // repair advice meant for a user's mesh.
    const std::string what = e.what();
    const size_t from = what.rfind("mesh: ", 0) == 0 ? 6 : 0;
    run.subdivision_failure =
        "its pieces are no manifold surface: " + what.substr(from, what.find(';') - from);
    return;
  }
  const Triangulation& delivered = *delivered_mesh;
  const std::vector<double> length3d = lengths_in_3d(delivered, positions);
  std::vector<std::array<double, 3>> flat;
  if (sub) {
    flat = drawn_sides(sub->corners);
  } else {
    flat.resize(delivered.num_faces());
    for (int f = 0; f < delivered.num_faces(); ++f) {
      for (int c = 0; c < 3; ++c) flat[f][c] = lengths[mesh.face_edge(f, c)];
    }
  }
  const std::vector<int> under = sub ? input_edge_under(mesh, delivered, *sub) : std::vector<int>{};
  const std::vector<char> allowed = on_input_edges(under);  // empty without pieces

  // === Seams and charts; charts whose faces overlap split between the sheets, until none does
  atlas.seconds = {};
  auto clock = Clock::now();
  // The flat corner angles of the faces at cones (the only ones a cone's wedges read).
  ConeWedges wedges{std::vector<double>(3 * static_cast<size_t>(delivered.num_faces()), 0.0),
                    kWidestWedge, kBranchEnd * std::sqrt(mesh.input_area())};
  std::vector<char> is_cone(delivered.num_vertices(), 0);
  for (int c : cones) is_cone[c] = 1;
  for (int f = 0; f < delivered.num_faces(); ++f) {
    const std::array<int, 3>& t = delivered.faces()[f];
    if (!is_cone[t[0]] && !is_cone[t[1]] && !is_cone[t[2]]) continue;
    const TriangleAngles a = corner_angles(Geometry::Euclidean, flat[f]);
    for (int c = 0; c < 3; ++c) wedges.corner_angles[3 * f + c] = a.angle[c];
  }
  std::vector<char> seam = cut_through_cones(delivered, length3d, cones, wedges, allowed).cut;
  Charts charts = lay_out_charts(delivered, flat, seam);
  std::vector<std::pair<int, int>> overlaps =
      overlapping_faces(delivered, seam, charts, {}, kPairsPerChart);
  const std::vector<int> group = sub ? sub->input_face : std::vector<int>{};
  std::vector<Eigen::Vector3d> centroid(sub ? mesh.num_faces() : delivered.num_faces(),
                                        Eigen::Vector3d::Zero());
  for (int f = 0; f < static_cast<int>(centroid.size()); ++f) {
    for (int v : mesh.faces()[f]) centroid[f] += mesh.positions()[v] / 3;
  }
  // Where two pieces of one input face overlap (its corner at a cone of several turns, on an
  // obtuse CAD triangle, opens past a full turn), no seam on the input's edges parts them: there
  // the pieces of that face are groups of their own, the seam inside it.
  const auto pieces_apart = [&](int face, std::vector<int>& finer,
                                std::vector<Eigen::Vector3d>& finer_centroid) {
    finer = group, finer_centroid = centroid;
    for (int h = 0; h < delivered.num_faces(); ++h) {
      if (group[h] != group[face]) continue;
      finer[h] = static_cast<int>(finer_centroid.size());
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int v : sub->faces[h]) c += sub->positions[v] / 3;
      finer_centroid.push_back(c);
    }
  };
  atlas.splits = 0;
  atlas.halvings = 0;
  // Each round parts the first overlapping pair of every chart, then, in their order, the further
  // pairs still in one piece while they overlap deeply (a piece keeps its chart's layout up to a
  // rigid motion, so such a pair still overlaps: it needs no new layout to be found again; a
  // shallow overlap of slivers may be rounding's, and it and the rest of its piece wait for the
  // next round's layout), then lays the pieces out.
  for (int round = 0; round < kMaxSplitRounds && !overlaps.empty(); ++round) {
    std::vector<int> part = charts.chart;
    int parts = charts.num_charts;
    // A piece that a pair could not part, or whose next pair overlaps shallowly: left to the next
    // round.
    std::vector<char> stuck(parts, 0);
    std::vector<char> split_once(parts, 0);
    SheetSeparator separator(delivered, part, length3d);
    for (const auto& [f, g] : overlaps) {
      if (part[f] != part[g] || stuck[part[f]]) continue;
      const bool first = part[f] < charts.num_charts && !split_once[part[f]];
      if (!first && !(overlap_depth(charts, f, g) > kDeepOverlap)) {
        stuck[part[f]] = 1;  // its next pair in the order waits for the next round, as this one
        continue;
      }
      if (part[f] < charts.num_charts) split_once[part[f]] = 1;
      int marked = 0;
      if (sub && group[f] == group[g]) {
        std::vector<int> finer;
        std::vector<Eigen::Vector3d> finer_centroid;
        pieces_apart(f, finer, finer_centroid);
        marked = separator.separate(parts, f, g, finer, finer_centroid, seam);
      } else {
        marked = separator.separate(parts, f, g, group, centroid, seam);
      }
      if (marked > 0) {
        ++atlas.splits, ++parts;
        stuck.push_back(0);
      } else {
        stuck[part[f]] = 1;
      }
    }
    connect_cut(delivered, length3d, seam, allowed);
    Charts parted = lay_out_charts(delivered, flat, seam);
    overlaps = overlapping_faces(delivered, seam, parted,
                                 unchanged_clean_charts(parted, charts, overlaps), kPairsPerChart);
    charts = std::move(parted);
  }
  // Charts still overlapping after the rounds: every pair, for the report.
  if (!overlaps.empty()) overlaps = overlapping_faces(delivered, seam, charts);
  // Long charts (a tube's strip) fill a square poorly: each is halved across its long axis (as
  // two sheets from its two ends), where that packs the square fuller by a tenth and leaves no
  // overlap. Only those packings are made here: the delivered attempt's charts are packed once
  // it is chosen (pack_atlas).
  atlas.seconds.charts += lap(clock);
  // The charts as they stand delivered on the user's faces, on the second core while a halving of
  // them is tried: most halvings pack no fuller, and then that delivery is the one made (CGAL's
  // man at 8 cones: its 0.07 s trial beside the delivery's 0.13 s); where one packs fuller, the
  // halved charts' delivery beside the next trial (CGAL's lion head at 8 cones: its second trial,
  // 0.034 s, beside the delivery's 0.030 s).
  const auto on_input = [&, bound = run.atlas.bound](const std::vector<char>& cut,
                                                     const Charts& developed) {
    return delivered_on_input(mesh, *sub, delivered, under, cut, developed, bound);
  };
  // A delivery runs on a thread of its own where one can be made, else (deferred) when asked
  // for; one that is not asked for is left to end or, deferred, never run.
  const auto running = [](const std::future<OnInput>& f) {
    return f.valid() && f.wait_for(std::chrono::seconds(0)) == std::future_status::timeout;
  };
  std::future<OnInput> beside;  // a delivery on the user's faces, of `charts` where `current`
  bool current = false;
  std::vector<std::future<OnInput>> outdated;  // of charts since halved, still running
  std::optional<Packing> packing;
  for (int round = 0; round < kMaxHalvings && o.halve_long_charts && overlaps.empty(); ++round) {
    const std::vector<std::pair<int, int>> ends = long_chart_ends(charts, kLongAspect);
    if (ends.empty()) {
      atlas.seconds.charts += lap(clock);
      break;
    }
    if (sub && !current) {
      // A delivery of charts since halved that still runs is left to end on its own (waiting for
      // it would hold this trial back); it reads `sub` until it ends.
      if (running(beside)) outdated.push_back(std::move(beside));
      auto delivery = [&, cut = seam, developed = charts] { return on_input(cut, developed); };
      try {
        beside = std::async(std::launch::async, delivery);
      } catch (const std::system_error&) {  // no second thread: delivered when asked for
        beside = std::async(std::launch::deferred, std::move(delivery));
      }
      current = true;
    }
    std::vector<char> halved = seam;
    std::vector<int> part = charts.chart;
    int count = 0;
    SheetSeparator separator(delivered, part);
    for (const auto& [f, g] : ends) {
      count += separator.separate(charts.num_charts + count, f, g, group, centroid, halved) > 0;
    }
    if (count == 0) {
      atlas.seconds.charts += lap(clock);
      break;
    }
    connect_cut(delivered, length3d, halved, allowed);
    Charts shorter = lay_out_charts(delivered, flat, halved);
    // The charts no halving touched are laid out as before, without overlap.
    const bool overlap =
        !overlapping_faces(delivered, halved, shorter, unchanged_clean_charts(shorter, charts, {}))
             .empty();
    atlas.seconds.charts += lap(clock);
    if (overlap) break;
    // (In quarter turns, the charts as delivered: turned to meet so.)
    const auto as_packed = [&](const Charts& c) {
      if (!quarter) return triangles_by_chart(c);
      Charts turned = c;
      turn_charts_to_quarter_turns(faces, turned);
      return triangles_by_chart(turned);
    };
    if (!packing) packing = pack_charts(as_packed(charts), packing_options);
    // Halved charts pack about as full as whole ones: that packing's utilization sizes the first
    // margin, mostly sparing the packing its second pass.
    Packing fuller = pack_charts(as_packed(shorter), packing_options, packing->utilization);
    atlas.seconds.packing += lap(clock);
    if (!(fuller.utilization > 1.1 * packing->utilization)) break;
    seam = std::move(halved);
    charts = std::move(shorter);
    packing = std::move(fuller);
    atlas.halvings += count;
    current = false;
  }
  // A common subdivision's charts moved onto the user's faces (charts_on_input), delivered where
  // they draw so (drawn_where_deliverable), measured against the pieces as developed; else with
  // the faces around those that do not draw cut into their pieces (partly_cut_drawn). Else the
  // pieces' charts with their insides drawn harmonic, their borders as developed: the pieces' new
  // vertices are where the flow's crossings put them, which costs conformality (the cow, 1.8k
  // flips: QC p95 1.376 as developed, 1.292 redrawn); a chart that the redrawing turns, overlaps or
  // makes less conformal (its QC p95) stays as developed.
  atlas.harmonic_charts = 0;
  if (sub && overlaps.empty()) {
    OnInput drawn = current ? beside.get() : on_input(seam, charts);
    if (drawn.user) {
      atlas.seconds.harmonic += lap(clock);
      atlas.harmonic_charts = drawn.user->redrawn;
      atlas.untangled = drawn.user->untangled;
      atlas.on_input_faces = true;
      deliver(mesh, mesh.positions(), mesh.faces(), drawn.in->seam,
              lengths_in_3d(mesh, mesh.positions()), drawn.user->charts, {}, mesh.input_area(),
              quarter, run);
      return;
    }
    if (drawn.partly) {
      auto& [cut, user] = *drawn.partly;
      atlas.seconds.harmonic += lap(clock);
      atlas.harmonic_charts = user.redrawn;
      atlas.untangled = user.untangled;
      atlas.input_faces_cut = cut.input_faces_cut;
      deliver(cut.delivered, cut.sub.positions, cut.sub.faces, cut.seam,
              lengths_in_3d(cut.delivered, cut.sub.positions), user.charts, {}, mesh.input_area(),
              quarter, run);
      run.subdivision = std::move(cut.sub);
      return;
    }
    atlas.seconds.harmonic += lap(clock);
    atlas.harmonic_charts = draw_harmonic_insides(delivered, positions, seam,
                                                  std::vector<char>(charts.num_charts, 1), charts);
    // A piece still turned (a sliver of two corners at one point, drawn a rounding past it, on a
    // CAD plate of needles, PrusaSlicer's CR-8 bed: its chart keeps its developed drawing, whose
    // pieces of no 3D area the harmonic one cannot draw) is untangled as the user's faces are; an
    // overlap that makes is found again.
    if (std::any_of(charts.corners.begin(), charts.corners.end(),
                    [](const auto& q) { return !(signed_area(q) > 0); })) {
      atlas.untangled =
          static_cast<int>(untangle_turned_faces(delivered, positions, seam, charts).size());
      if (atlas.untangled > 0) overlaps = overlapping_faces(delivered, seam, charts);
    }
    atlas.seconds.harmonic += lap(clock);
  }
  // A delivery made beside a halving that was kept reads `sub` until it ends.
  if (running(beside)) beside.wait();
  for (std::future<OnInput>& f : outdated) f.wait();
  deliver(delivered, positions, faces, seam, length3d, charts, overlaps, mesh.input_area(), quarter,
          run);
  if (sub) run.subdivision = std::move(sub);
}

void pack_atlas(const PackingOptions& o, Uniformization& run) {
  if (run.layout_kind != LayoutKind::Atlas || run.corners.empty() || !run.atlas.texture.empty()) {
    return;
  }
  AtlasResult& atlas = run.atlas;
  const auto start = Clock::now();
  PackingOptions packing_options = o;
  packing_options.quarter_turns_only = atlas.quarter_turns;
  std::vector<std::vector<std::array<Eigen::Vector2d, 3>>> by_chart(atlas.num_charts);
  for (size_t f = 0; f < run.corners.size(); ++f) {
    const auto& q = run.corners[f];
    by_chart[run.face_chart[f]].push_back({q[0].head<2>(), q[1].head<2>(), q[2].head<2>()});
  }
  const Packing packing = pack_charts(by_chart, packing_options);
  atlas.utilization = packing.utilization;
  atlas.padding = packing.padding;
  atlas.padding_asked = o.padding;
  atlas.charts_below_a_texel = packing.below_a_texel;
  atlas.texture.resize(run.corners.size());
  for (size_t f = 0; f < run.corners.size(); ++f) {
    const int k = run.face_chart[f];
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector2d uv =
          packing.scale * packing.rotation[k] * run.corners[f][c].head<2>() + packing.offset[k];
      atlas.texture[f][c] = uv.cwiseMax(0.0).cwiseMin(1.0);  // rounding past the square's sides
    }
  }
  atlas.seconds.packing += seconds_since(start);
}

std::string atlas_failure(const Uniformization& run) {
  if (run.layout_kind != LayoutKind::Atlas) return "";
  if (run.corners.empty()) {
    return "the atlas has no layout: the common subdivision could not be built (" +
           run.subdivision_failure + ")";
  }
  if (run.atlas.overlapping_faces == 0) return "";
  std::ostringstream s;
  s << run.atlas.overlapping_faces << " faces of the atlas overlap other faces of their chart";
  return s.str();
}

}  // namespace ricci::detail
