// An atlas drawn on a common subdivision, moved onto the user's own triangles, and when that is
// delivered (pipeline/texture_atlas.h).
//
// The seams run on the user's edges, so each input face lies in one chart, and its corners are
// vertices of the subdivision: the charts' corners at the input's vertices are the flat cone
// metric's, and a chart's border between two of them, a polyline through the subdivision's new
// vertices, becomes its chord. The two sides of a seam are congruent polylines, so their chords
// are equal too: the seams still glue.
#include <algorithm>
#include <limits>
#include <optional>
#include <utility>

#include "pipeline/texture_atlas.h"
#include "ricci/layout/charts.h"
#include "ricci/mesh/geometry.h"
#include "ricci/pipeline/layout_quality.h"

namespace ricci::detail {

std::optional<InputCharts> charts_on_input(const CompactMesh& mesh, const CommonSubdivision& sub,
                                           const Triangulation& delivered,
                                           const std::vector<int>& under,
                                           const std::vector<char>& seam, const Charts& charts) {
  const int nv = mesh.num_vertices();
  if (sub.num_input_vertices != nv) return std::nullopt;  // not this mesh's subdivision
  // Per input edge its delivered edges and how many of them are seams: all or none.
  InputCharts out;
  out.seam.assign(mesh.num_edges(), 0);
  std::vector<int> pieces(mesh.num_edges(), 0), seams(mesh.num_edges(), 0);
  for (int e = 0; e < delivered.num_edges(); ++e) {
    const int on = under[e];
    if (on < 0) {
      if (seam[e]) return std::nullopt;  // a seam inside an input face
      continue;
    }
    ++pieces[on];
    seams[on] += seam[e] != 0;
  }
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (seams[e] != 0 && seams[e] != pieces[e]) return std::nullopt;
    out.seam[e] = seams[e] != 0;
  }
  // Per input face, its pieces' chart and its corners where they put them.
  Charts& in = out.charts;
  in.num_charts = charts.num_charts;
  in.chart.assign(mesh.num_faces(), -1);
  in.corners.resize(mesh.num_faces());
  std::vector<char> placed(3 * static_cast<size_t>(mesh.num_faces()), 0);
  for (int h = 0; h < delivered.num_faces(); ++h) {
    const int f = sub.input_face[h];
    if (in.chart[f] >= 0 && in.chart[f] != charts.chart[h]) return std::nullopt;
    in.chart[f] = charts.chart[h];
    for (int k = 0; k < 3; ++k) {
      const int v = sub.faces[h][k];
      if (v >= nv) continue;
      for (int c = 0; c < 3; ++c) {
        if (mesh.faces()[f][c] != v) continue;
        in.corners[f][c] = charts.corners[h][k];
        placed[3 * static_cast<size_t>(f) + c] = 1;
      }
    }
  }
  if (std::find(placed.begin(), placed.end(), 0) != placed.end()) return std::nullopt;
  in.max_relative_length_error = charts.max_relative_length_error;
  return out;
}

std::vector<char> pieces_closure(const CompactMesh& mesh, const std::vector<int>& under,
                                 const std::vector<int>& faces) {
  std::vector<int> pieces(mesh.num_edges(), 0);
  for (int e : under) {
    if (e >= 0) ++pieces[e];
  }
  std::vector<char> cut_up(mesh.num_faces(), 0);
  std::vector<int> queue;
  for (int f : faces) {
    if (!cut_up[f]) cut_up[f] = 1, queue.push_back(f);
  }
  while (!queue.empty()) {
    const int f = queue.back();
    queue.pop_back();
    for (int c = 0; c < 3; ++c) {
      if (pieces[mesh.face_edge(f, c)] < 2) continue;
      const int across = mesh.twin(3 * f + c);
      if (across >= 0 && !cut_up[across / 3]) cut_up[across / 3] = 1, queue.push_back(across / 3);
    }
  }
  return cut_up;
}

PartlyCutCharts partly_cut_charts(const CompactMesh& mesh, const CommonSubdivision& sub,
                                  const Triangulation& delivered, const std::vector<char>& seam,
                                  const Charts& pieces, const InputCharts& in,
                                  const std::vector<char>& cut_up) {
  const int nv = mesh.num_vertices();
  CommonSubdivision s;
  s.num_input_vertices = nv;
  s.num_flips = sub.num_flips;
  s.seconds = sub.seconds;
  // Each input face's pieces; a face of one piece is its own (its corners the piece's).
  std::vector<std::vector<int>> pieces_of(mesh.num_faces());
  for (int h = 0; h < delivered.num_faces(); ++h) {
    if (cut_up[sub.input_face[h]]) pieces_of[sub.input_face[h]].push_back(h);
  }
  // The vertices: the input's, then the new ones that the cut faces' pieces hold.
  std::vector<int> index(sub.positions.size(), -1);
  std::vector<int> kept;
  for (int v = 0; v < nv; ++v) index[v] = v, kept.push_back(v);
  for (const std::vector<int>& list : pieces_of) {
    for (int h : list) {
      for (int v : sub.faces[h]) {
        if (index[v] < 0) index[v] = static_cast<int>(kept.size()), kept.push_back(v);
      }
    }
  }
  s.u.resize(static_cast<long>(kept.size()));
  for (size_t i = 0; i < kept.size(); ++i) {
    const int v = kept[i];
    s.positions.push_back(sub.positions[v]);
    s.u[static_cast<long>(i)] = sub.u[v];
    s.vertex_input_face.push_back(sub.vertex_input_face[v]);
    s.vertex_barycentric.push_back(sub.vertex_barycentric[v]);
    if (v >= nv) {
      s.vertex_input_edge.push_back(sub.vertex_input_edge[v - nv]);
      s.vertex_edge_parameter.push_back(sub.vertex_edge_parameter[v - nv]);
    }
  }
  // The faces in the input's order, a cut one's pieces in its place, each with its chart, its
  // corners and the seams of its sides.
  Charts charts;
  int input_faces_cut = 0;
  charts.num_charts = pieces.num_charts;
  charts.max_relative_length_error = pieces.max_relative_length_error;
  std::vector<std::array<char, 3>> side_seam;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const std::array<int, 3>& own = mesh.faces()[f];
    if (pieces_of[f].size() > 1) {
      ++input_faces_cut;
      for (int h : pieces_of[f]) {
        std::array<int, 3> t{};
        std::array<char, 3> on{};
        for (int c = 0; c < 3; ++c) {
          t[c] = index[sub.faces[h][c]];
          on[c] = seam[delivered.face_edge(h, c)];
        }
        s.faces.push_back(t);
        s.input_face.push_back(f);
        s.final_face.push_back(sub.final_face[h]);
        charts.chart.push_back(pieces.chart[h]);
        charts.corners.push_back(pieces.corners[h]);
        side_seam.push_back(on);
      }
      continue;
    }
    std::array<char, 3> on{};
    for (int c = 0; c < 3; ++c) on[c] = in.seam[mesh.face_edge(f, c)];
    s.faces.push_back(own);
    s.input_face.push_back(f);
    side_seam.push_back(on);
    if (pieces_of[f].empty()) {
      s.final_face.push_back(-1);
      charts.chart.push_back(in.charts.chart[f]);
      charts.corners.push_back(in.charts.corners[f]);
      continue;
    }
    // Its one piece: the face itself, its corners from a turn of the piece's.
    const int h = pieces_of[f][0];
    int turn = 0;
    while (turn < 2 && sub.faces[h][turn] != own[0]) ++turn;
    s.final_face.push_back(sub.final_face[h]);
    charts.chart.push_back(pieces.chart[h]);
    charts.corners.push_back({pieces.corners[h][turn], pieces.corners[h][(turn + 1) % 3],
                              pieces.corners[h][(turn + 2) % 3]});
  }
  Triangulation t = Triangulation::from_faces(static_cast<int>(kept.size()), s.faces);
  std::vector<char> sides(t.num_edges(), 0);
  for (int f = 0; f < t.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) sides[t.face_edge(f, c)] |= side_seam[f][c];
  }
  s.corners.resize(s.faces.size());
  s.vertex_layout.assign(kept.size(), Eigen::Vector3d::Zero());
  for (size_t f = 0; f < s.faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector2d& q = charts.corners[f][c];
      s.corners[f][c] = Eigen::Vector3d(q.x(), q.y(), 0);
    }
  }
  for (size_t f = s.faces.size(); f-- > 0;) {  // each vertex from the first face that holds it
    for (int c = 0; c < 3; ++c) s.vertex_layout[s.faces[f][c]] = s.corners[f][c];
  }
  return {std::move(s), std::move(t), std::move(sides), std::move(charts), input_faces_cut};
}

namespace {

// The user's faces as developed are redrawn harmonic inside where their QC p95 exceeds 1 by more
// than this much more than the pieces' as developed does: the two percentiles sample the same map
// (the input's vertices where the pieces put them) over other triangles, and differ there by what
// the sampling moves them. On the real-mesh set and CGAL's: the glmark2 bunny's 69,666 faces
// 1.0431 against its pieces' 1.0456, the DTC hull's 116,062 faces 1.02997 against 1.02994, the
// 99,739-face PyMeshFix bunny 1.0307 against 1.0302 (1.6 % of the excess).
constexpr double kSameQc = 0.02;

// Below this many faces the user's faces are drawn harmonic inside whatever their QC as developed:
// the factorization costs little there, and a drawing as conformal as the pieces as developed can
// still gain from it (CGAL's triceratops, 5,660 faces: QC p95 1.4304 as developed, its pieces'
// 1.4308, 1.403 drawn harmonic). Above it the factorization costs more (the genus-3 refined
// elephant's 88,928 faces at 8 cones: about 0.2 s more of its 3 s) and moves QC p95 less (by at
// most 8 % of its excess over 1 above 1,700 faces on the files with a subdivision).
constexpr int kHarmonicBelow = 20000;

// Above the bound (a cone budget stopped the placement, or the user gave the cones) the user's
// faces' D is taken as the pieces' within this fraction of it: the same map sampled over other
// triangles. At 8 cones the glmark2 bunny's 69,666 faces have 0.46995 and its pieces as developed
// 0.46993, the cow's 5,804 faces 1.23485 and its pieces 1.23417.
constexpr double kSameD = 0.02;

// Rounds of faces cut into their pieces around those still turned or overlapping, and the share
// of the input's faces cut beyond which the pieces are delivered.
constexpr int kPartlyCutRounds = 3;
constexpr double kMostCut = 0.5;
// The user's faces but a few cut are delivered where their QC p95 exceeds 1 by at most this many
// times what the pieces' as developed does (which is above theirs drawn harmonic: the cow's 1.376
// against 1.292). A coarse part's faces are less conformal than its pieces (on the real set and
// CGAL's, up to 1.42 times the excess of the pieces drawn harmonic, delivered before: the
// joint's 3.10 against 2.48); on the 180 faces of CGAL's mpi, slivers of 3D, 28.5 against 2.81.
constexpr double kPartlyCutQc = 2;

}  // namespace

double qc_p95(const std::vector<Eigen::Vector3d>& positions,
              const std::vector<std::array<int, 3>>& faces,
              const std::vector<std::array<Eigen::Vector2d, 3>>& corners) {
  std::vector<double> qc(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    qc[f] = drawn_quasi_conformal_ratio(positions, faces[f], corners[f]);
  }
  return quantile(std::move(qc), 0.95);
}

// Charts as developed on the pieces, moved onto other faces `t` (the user's, or the user's with
// some cut into their pieces), turned faces untangled; where a face stays turned, the faces are
// fewer than kHarmonicBelow, or QC p95 is above the pieces' as developed (by more than kSameQc of
// its excess over 1), their insides drawn harmonic where that is more nearly conformal (the
// drawing as developed kept where it turned no face and the redrawn one is less conformal over all
// the faces, or would not deliver), and untangled again. Given where no face turns over or
// overlaps another of its chart and D is within `bound` or within kSameD of the pieces' (`bound`
// NaN: the latter), whatever their QC: the user's triangles are the surface asked for, and a
// piecewise linear map on them is as conformal as their shapes let it be (a coarse part's map is
// less so than on the pieces that subdivide its faces, drawn harmonic inside: simbody's 28-face
// pelvis part QC p95 19.9 against 3.80, the 19,994-face dragon 1.306 against 1.214, the
// 99,739-face bunny 1.0307 against 1.0289). The harmonic drawing costs a factorization, and on
// the faces of a fine mesh it moves QC p95 little: on the 160 files of the real-mesh set and
// CGAL's with a subdivision, by at most 8 % of its excess over 1 above 1,700 faces, 30 % above 500
// (and up to 14 times on a part of 92). Where not given, `stuck` gets the faces that stay turned
// or overlap another (none where D alone exceeds), of the redrawn drawing, else of the one as
// developed.
std::optional<Drawn> drawn_where_deliverable(const Triangulation& t,
                                             const std::vector<Eigen::Vector3d>& positions,
                                             const std::vector<char>& seam, Charts charts,
                                             double bound, const AsDrawn& pieces,
                                             std::vector<int>& stuck) {
  const std::vector<std::array<int, 3>>& faces = t.faces();
  Drawn drawn;
  const auto turned = [&] {
    return std::any_of(charts.corners.begin(), charts.corners.end(),
                       [](const auto& q) { return !(signed_area(q) > 0); });
  };
  // A drawing's D and its faces that overlap others of their chart, found once per drawing.
  struct Checked {
    double distortion = 0;
    std::vector<std::pair<int, int>> overlaps;
  };
  const auto check = [&](const Charts& c) {
    return Checked{face_distortion(positions, faces, c.corners), overlapping_faces(t, seam, c)};
  };
  // D within the bound or kSameD of the pieces', and no two faces of a chart overlapping.
  const auto deliverable = [&](const Checked& k) {
    return (k.distortion <= bound || !(k.distortion > (1 + kSameD) * pieces.distortion)) &&
           k.overlaps.empty();
  };
  // The faces of drawing c (checked as k) turned or overlapping another; of `also` (checked as
  // `also_checked`, or here) where c has none.
  const auto not_given = [&](const Charts& c, const Checked& k, const Charts* also = nullptr,
                             std::optional<Checked> also_checked = std::nullopt) {
    const auto add = [&](const Charts& d, const Checked& kd) {
      for (int f = 0; f < t.num_faces(); ++f) {
        if (!(signed_area(d.corners[f]) > 0)) stuck.push_back(f);
      }
      for (const auto& [f, g] : kd.overlaps) stuck.push_back(f), stuck.push_back(g);
    };
    stuck.clear();
    add(c, k);
    if (stuck.empty() && also != nullptr) add(*also, also_checked ? *also_checked : check(*also));
    return std::nullopt;
  };
  std::vector<int> moved = untangle_turned_faces(t, positions, seam, charts);
  const bool turned_developed = turned();
  // QC p95 as developed, measured where it is compared (not where a face stays turned).
  const double qc_developed = turned_developed ? std::numeric_limits<double>::quiet_NaN()
                                               : qc_p95(positions, faces, charts.corners);
  if (turned_developed || t.num_faces() < kHarmonicBelow ||
      qc_developed - 1 > (1 + kSameQc) * (pieces.qc_p95 - 1)) {
    const Charts untangled = charts;
    const std::vector<int> moved_untangled = moved;
    drawn.redrawn =
        draw_harmonic_insides(t, positions, seam, std::vector<char>(charts.num_charts, 1), charts);
    // Where the drawing as developed turned no face, the redrawn one is kept only where QC p95
    // over all the faces is no higher, too: each chart's can fall while the whole's rises (Cura's
    // nozzle at 8 cones: 1.430 as developed, 1.459 redrawn).
    if (!turned_developed && drawn.redrawn > 0 &&
        !(qc_p95(positions, faces, charts.corners) <= qc_developed)) {
      charts = untangled;
      drawn.redrawn = 0;
    }
    // The wedges moved before and not redrawn since, and those moved again.
    std::vector<int> kept;
    for (int w : moved) {
      if (charts.corners[w / 3][w % 3] == untangled.corners[w / 3][w % 3]) kept.push_back(w);
    }
    moved = std::move(kept);
    for (int w : untangle_turned_faces(t, positions, seam, charts)) {
      if (std::find(moved.begin(), moved.end(), w) == moved.end()) moved.push_back(w);
    }
    const Checked now = check(charts);
    if (turned() || !deliverable(now)) {
      // The drawing as developed, where it turned no face and delivers.
      std::optional<Checked> before;
      if (!turned_developed && drawn.redrawn > 0) before = check(untangled);
      if (!before || !deliverable(*before)) return not_given(charts, now, &untangled, before);
      charts = untangled;
      moved = moved_untangled;
      drawn.redrawn = 0;
    }
  } else if (const Checked now = check(charts); !deliverable(now)) {
    return not_given(charts, now);
  }
  drawn.untangled = static_cast<int>(moved.size());
  drawn.charts = std::move(charts);
  return drawn;
}

// The atlas delivered on the user's faces, with those around faces that cannot be drawn there
// (a cone opening their corner past a half turn: CGAL's man, 3 of 34,986 faces) cut into their
// pieces, out to input edges no new vertex splits, so that the delivered mesh conforms. While
// that does not deliver (faces still turned or overlapping, or D above the bound), for
// kPartlyCutRounds in all, the faces across the sides of the stuck ones cut already are cut too,
// and the faces stuck since. `stuck`: the input faces that turned or overlapped on the user's
// faces.
std::optional<std::pair<PartlyCutCharts, Drawn>> partly_cut_drawn(
    const CompactMesh& mesh, const CommonSubdivision& sub, const Triangulation& delivered,
    const std::vector<int>& under, const std::vector<char>& seam, const Charts& developed,
    const InputCharts& in, double bound, const AsDrawn& pieces, std::vector<int> stuck) {
  std::vector<char> cut_up(mesh.num_faces(), 0);
  for (int round = 0; round < kPartlyCutRounds && !stuck.empty(); ++round) {
    // The faces stuck, and across the sides of those cut already the faces around them.
    std::vector<int> grow = stuck;
    for (int f : stuck) {
      if (!cut_up[f]) continue;
      for (int c = 0; c < 3; ++c) {
        const int across = mesh.twin(3 * f + c);
        if (across >= 0) grow.push_back(across / 3);
      }
    }
    const std::vector<char> more = pieces_closure(mesh, under, grow);
    if (more == cut_up) break;
    cut_up = more;
    if (static_cast<double>(std::count(cut_up.begin(), cut_up.end(), 1)) >
        kMostCut * mesh.num_faces()) {
      break;
    }
    PartlyCutCharts partly = partly_cut_charts(mesh, sub, delivered, seam, developed, in, cut_up);
    // No face of more than one piece cut: the drawing that did not deliver, again.
    if (partly.input_faces_cut == 0) continue;
    std::vector<int> again;
    std::optional<Drawn> drawn = drawn_where_deliverable(
        partly.delivered, partly.sub.positions, partly.seam, partly.charts, bound, pieces, again);
    if (drawn) {
      const double qc = qc_p95(partly.sub.positions, partly.sub.faces, drawn->charts.corners);
      if (!(qc - 1 <= kPartlyCutQc * (pieces.qc_p95 - 1))) return std::nullopt;
      return std::make_pair(std::move(partly), std::move(*drawn));
    }
    for (int g : again) stuck.push_back(partly.sub.input_face[g]);
  }
  return std::nullopt;
}

OnInput delivered_on_input(const CompactMesh& mesh, const CommonSubdivision& sub,
                           const Triangulation& delivered, const std::vector<int>& under,
                           const std::vector<char>& seam, const Charts& charts, double bound) {
  OnInput out;
  const AsDrawn pieces{face_distortion(sub.positions, sub.faces, charts.corners),
                       qc_p95(sub.positions, sub.faces, charts.corners)};
  out.in = charts_on_input(mesh, sub, delivered, under, seam, charts);
  if (!out.in) return out;
  std::vector<int> stuck;
  out.user = drawn_where_deliverable(mesh, mesh.positions(), out.in->seam, out.in->charts, bound,
                                     pieces, stuck);
  if (!out.user) {
    out.partly = partly_cut_drawn(mesh, sub, delivered, under, seam, charts, *out.in, bound, pieces,
                                  std::move(stuck));
  }
  return out;
}

}  // namespace ricci::detail
