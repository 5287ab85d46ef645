#include "pipeline/doubled_surface.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "flow/delaunay.h"
#include "layout/layout_methods.h"
#include "pipeline/circle_domain.h"
#include "pipeline/delivered_layout.h"
#include "pipeline/texture_atlas.h"
#include "ricci/flow/presets.h"
#include "ricci/flow/ricci_flow.h"
#include "ricci/flow/scheme.h"
#include "ricci/layout/charts.h"
#include "ricci/layout/seams.h"
#include "ricci/mesh/errors.h"
#include "ricci/mesh/geometry.h"
#include "subdivision/input_overlay.h"

namespace ricci::detail {

bool double_follows_boundary_stall(const CompactMesh& half, const UniformizationOptions& options,
                                   const TargetCurvature& target, const Uniformization& run) {
  const LayoutKind kind = planned_layout(half, run.preset, run.geometry);
  // With u held fixed (free boundary) a stall in both classes of the surface itself is left as
  // it is: such targets go to the double only from a converged flow in another class
  // (class_other_than_doubles), where the boundary between its vertices may change length. The
  // atlas holds u at its cones and on the boundary only for the distortion's sake: its boundary
  // may become the geodesics between the boundary's vertices.
  const bool atlas = run.preset == TargetPreset::Atlas;
  return !half.is_closed() && (target.num_fixed() == 0 || atlas) &&
         options.flow.edge_flips != EdgeFlips::Never && is_yamabe(run.structure) &&
         ((run.geometry == Geometry::Euclidean && (kind == LayoutKind::Plane || atlas)) ||
          (run.geometry == Geometry::Hyperbolic && kind == LayoutKind::PoincareDisk));
}

bool may_flow_on_double(const CompactMesh& half, const UniformizationOptions& options,
                        const TargetCurvature& target, const Uniformization& run) {
  return !run.result.converged && run.result.stalled_at_boundary && run.double_failure.empty() &&
         double_follows_boundary_stall(half, options, target, run);
}

namespace {

// The boundary edges of `t` whose opposite angle, with `lengths` per edge, exceeds a right angle:
// a^2 + b^2 < c^2, with a margin of rounding (a cocircular pair of a face and its mirror image is
// Delaunay either way). On the double such an edge and its mirror image are not Delaunay.
int obtuse_boundary_edges(const Triangulation& t, const std::vector<double>& lengths) {
  int count = 0;
  for (int f = 0; f < t.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int e = t.face_edge(f, c);
      if (!t.is_boundary_edge(e)) continue;
      const double a = lengths[t.face_edge(f, (c + 1) % 3)];
      const double b = lengths[t.face_edge(f, (c + 2) % 3)];
      count += a * a + b * b < lengths[e] * lengths[e] * (1 - 1e-12);
    }
  }
  return count;
}

}  // namespace

std::string class_other_than_doubles(const CompactMesh& half, const UniformizationOptions& options,
                                     const Uniformization& run) {
  const FlowResult& r = run.result;
  const LayoutKind kind = planned_layout(half, run.preset, run.geometry);
  if (!r.converged || half.is_closed() || run.geometry != Geometry::Euclidean ||
      !is_yamabe(run.structure) || r.flip_sequence.empty() ||
      options.flow.edge_flips == EdgeFlips::Never || !options.flow.delaunay_class ||
      options.keep_input_triangulation ||
      (kind != LayoutKind::Plane && kind != LayoutKind::PlaneCut)) {
    return "";
  }
  // Not for the atlas either: on the 44 files of the real-mesh set and CGAL's whose atlas parts
  // would go to the double, its QC p95 fell on 8 (oblong-shuffled 3.13 to 2.64) and rose on 5
  // (geomview-hook 2.25 to 2.59), D within 0.01, at up to 3.5 times the time
  // (pymeshfix-bunny 3.4 to 6.0 s); no atlas failed or overlapped either way.
  // Not for the disk preset: its circles are fitted by repeated flows, which on the double cost
  // up to 20 times the half's (pymeshlab-bunny10k.obj: 0.39 s to 7.8 s, QC p95 1.404 to 1.405).
  if (run.preset == TargetPreset::UnitDisk) return "";
  // At u = 0 every class's metric is the input's (the flips to either Delaunay triangulation are
  // isometric): nothing to flow again.
  if (r.u.size() == 0 || r.u.cwiseAbs().maxCoeff() <= 1e-12) return "";
  if (!r.input_class_because.empty()) {
    return "converged only in the input triangulation's class (" + r.input_class_because + ")";
  }
  // The two classes differ where the half's intrinsic Delaunay triangulation of the input metric,
  // where its class starts, is not the double's, or where its final one is not.
  IntrinsicTriangulation start(half);
  ConformalStructure structure = run.structure;
  make_input_delaunay(start, structure);
  std::vector<double> input(start.num_edges());
  for (int e = 0; e < start.num_edges(); ++e) input[e] = std::sqrt(2 * structure.eta[e]);
  const int at_start = obtuse_boundary_edges(start, input);
  const int at_end = r.edge_lengths.empty()
                         ? 0
                         : obtuse_boundary_edges(result_triangulation(half, r), r.edge_lengths);
  if (at_start == 0 && at_end == 0) return "";
  std::ostringstream s;
  s << "converged in the class of its intrinsic Delaunay triangulation, but of its boundary edges "
    << at_start
    << " face an angle above a right angle in that triangulation of the input metric and " << at_end
    << " in the final one, so that class is not its double's";
  return s.str();
}

TargetCurvature doubled_target(const CompactMesh& half, const CompactMesh& twice,
                               const TargetCurvature& target) {
  const int n = half.num_vertices();
  TargetCurvature t;
  t.curvature = Eigen::VectorXd::Zero(twice.num_vertices());
  t.fixed.assign(twice.num_vertices(), 0);
  int copy = n;
  for (int v = 0; v < n; ++v) {
    const bool boundary = half.is_boundary_vertex(v);
    const double k = (boundary ? 2.0 : 1.0) * target.curvature[v];
    t.curvature[v] = k;
    t.fixed[v] = target.fixed[v];
    if (boundary) continue;
    t.curvature[copy] = k;
    t.fixed[copy] = target.fixed[v];
    ++copy;
  }
  return t;
}

FlowResult half_result(const CompactMesh& half, const FlowResult& twice) {
  FlowResult r = twice;
  const int n = half.num_vertices();
  for (Eigen::VectorXd* x : {&r.u, &r.radius, &r.curvature, &r.target}) {
    if (x->size() == 0) continue;
    x->conservativeResize(n);
    for (int v = 0; v < n; ++v) {
      if (half.is_boundary_vertex(v) && (x == &r.curvature || x == &r.target)) (*x)[v] /= 2;
    }
  }
  r.edge_lengths.clear();
  r.triangulation.reset();
  r.flip_sequence.clear();
  r.area = twice.area / 2;
  return r;
}

Layout face_by_face_layout(const Triangulation& mesh, Geometry geometry,
                           const std::vector<double>& lengths) {
  Layout layout;
  layout.geometry = geometry;
  layout.corners.resize(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    // Sides: corner 0 to 1 is the edge opposite corner 2, and so on.
    const double a = lengths[mesh.face_edge(f, 2)], b = lengths[mesh.face_edge(f, 1)],
                 c = lengths[mesh.face_edge(f, 0)];
    if (geometry == Geometry::Hyperbolic) {
      // Corner 0 at the centre of the Poincare disk, where a geodesic of length d from it ends
      // at radius tanh(d / 2).
      const double angle = corner_angles(geometry, {c, b, a}).angle[0];
      const std::complex<double> z = std::polar(std::tanh(b / 2), angle);
      layout.corners[f] = {Eigen::Vector3d::Zero(), Eigen::Vector3d(std::tanh(a / 2), 0, 0),
                           Eigen::Vector3d(z.real(), z.imag(), 0)};
      continue;
    }
    const auto [x, y] = triangle_apex(a, b, c);
    layout.corners[f] = {Eigen::Vector3d::Zero(), Eigen::Vector3d(a, 0, 0),
                         Eigen::Vector3d(x, y, 0)};
  }
  return layout;
}

namespace {

// The corners of face g when its side `side` is the side of an unfolded neighbour from `from` to
// `to` (the neighbour's orientation: g runs that side from `to` to `from`; for the strip's first
// face, where to go from `to`): the apex from g's lengths, left of to -> from.
std::array<Eigen::Vector2d, 3> unfold_across(const Triangulation& t,
                                             const std::vector<double>& lengths, int g, int side,
                                             const Eigen::Vector2d& from,
                                             const Eigen::Vector2d& to) {
  std::array<Eigen::Vector2d, 3> p;
  p[(side + 1) % 3] = to;
  p[(side + 2) % 3] = from;
  const Eigen::Vector2d d = from - to;
  const double base = d.norm();
  const auto [x, y] = triangle_apex(base, lengths[t.face_edge(g, (side + 2) % 3)],
                                    lengths[t.face_edge(g, (side + 1) % 3)]);
  const Eigen::Vector2d e = d / base;
  p[side] = to + x * e + y * Eigen::Vector2d(-e.y(), e.x());
  return p;
}

// The side of face g that is edge e, or -1 (also where e is two of its sides).
int side_of(const Triangulation& t, int g, int e) {
  int side = -1;
  for (int k = 0; k < 3; ++k) {
    if (t.face_edge(g, k) != e) continue;
    if (side >= 0) return -1;
    side = k;
  }
  return side;
}

}  // namespace

std::vector<double> boundary_lengths_on_double(const CompactMesh& half, const CompactMesh& twice,
                                               const FlowResult& result) {
  InputOverlay overlay(twice, true);
  for (const EdgeFlip& f : result.flip_sequence) overlay.flip(f);
  const IntrinsicTriangulation& t = overlay.triangulation();
  const std::vector<double>& lengths = result.edge_lengths;
  const std::vector<Crossing>& crossings = overlay.crossings();
  std::vector<double> out(half.num_edges(), 0.0);
  for (int e = 0; e < t.num_edges(); ++e) {
    const int input = overlay.coincident_input_edge(e);
    if (input >= 0 && input < half.num_edges() && half.is_boundary_edge(input)) {
      out[input] = lengths[e];
    }
  }
  for (int input = 0; input < half.num_edges(); ++input) {
    int c = overlay.first_crossing(input);
    if (!half.is_boundary_edge(input) || c < 0) continue;
    const auto [a, b] = twice.edge_vertices(input);
    // The face the edge leaves its first vertex into, drawn with that vertex at its corner.
    const Crossing& first = crossings[c];
    int face = t.edge_faces(first.edge)[first.forward ? 0 : 1];
    if (face < 0) return {};
    int side = side_of(t, face, first.edge);
    if (side < 0 || t.face_vertex(face, side) != a) return {};
    std::array<Eigen::Vector2d, 3> p = unfold_across(
        t, lengths, face, side, Eigen::Vector2d(lengths[first.edge], 0), Eigen::Vector2d::Zero());
    const Eigen::Vector2d start = p[side];
    // Across each crossed edge into the next face, to the one whose corner is the last vertex.
    for (; c >= 0; c = crossings[c].next) {
      const Crossing& x = crossings[c];
      if (t.edge_faces(x.edge)[x.forward ? 0 : 1] != face || t.face_edge(face, side) != x.edge) {
        return {};
      }
      const int next = t.edge_faces(x.edge)[x.forward ? 1 : 0];
      if (next < 0) return {};
      const int next_side = side_of(t, next, x.edge);
      if (next_side < 0) return {};
      p = unfold_across(t, lengths, next, next_side, p[(side + 1) % 3], p[(side + 2) % 3]);
      face = next;
      side = next_side;
      if (x.next >= 0) {
        side = side_of(t, face, crossings[x.next].edge);
        if (side < 0 || side == next_side) return {};
      }
    }
    if (t.face_vertex(face, side) != b) return {};
    out[input] = (p[side] - start).norm();
  }
  for (int e = 0; e < half.num_edges(); ++e) {
    if (half.is_boundary_edge(e) && !(out[e] > 0)) return {};  // neither an edge nor crossed
  }
  return out;
}

namespace {

// The double's common subdivision cut down to the half.
HalfSubdivision subdivide_half(const CompactMesh& half, const CompactMesh& twice,
                               const ConformalStructure& structure, const FlowResult& result,
                               PieceTriangles triangles) {
  const Geometry g = structure.geometry;
  const Triangulation& flowed = result_triangulation(twice, result);
  const Layout frames = face_by_face_layout(flowed, g, result.edge_lengths);
  return half_subdivision(
      half,
      common_subdivision(twice, structure, result, frames, DiskSidePoints::OnGeodesic, triangles),
      flowed, frames);
}

// A half of several boundary loops or of genus above 0, flat: cut open on the input's edges
// through every boundary loop and 2g loops (the atlas's seams without cones: one disk), its pieces
// developed in one chart, each by the rigid motion of its own drawn corners onto its placed side
// (the developed half's one position per vertex would not close around a loop; drawn from their
// side lengths, slivers' angles move by those lengths' rounding over their widths).
// \throws LayoutError when that is not one chart with every piece counter-clockwise.
std::vector<std::array<Eigen::Vector3d, 3>> cut_open_pieces(const CompactMesh& half,
                                                            const HalfSubdivision& last,
                                                            CutGraph& cut) {
  const CommonSubdivision& sub = last.subdivision;
  const Triangulation delivered =
      Triangulation::from_faces(static_cast<int>(sub.positions.size()), sub.faces);
  const std::vector<double> length3d = lengths_in_3d(delivered, sub.positions);
  std::vector<std::array<Eigen::Vector2d, 3>> drawn(last.piece_corners.size());
  for (size_t f = 0; f < drawn.size(); ++f) {
    for (int c = 0; c < 3; ++c) drawn[f][c] = last.piece_corners[f][c].head<2>();
  }
  cut = cut_through_cones(delivered, length3d, {}, {}, on_input_edges(half, delivered, sub));
  const Charts charts = lay_out_charts(delivered, drawn, cut.cut);
  // One chart, every piece counter-clockwise, every side as long as its piece's: a disk's
  // development (around a loop left uncut the lengths would not agree). The corners are the means
  // of their pieces' (lay_out_charts), which the development's rounding moves on slivers: angle
  // sums within 7.7e-9 of 2 pi on the real-mesh set and CGAL's (cura-robot-support.stl).
  if (charts.num_charts != 1 || charts.flipped_faces > 0 ||
      !(charts.max_relative_length_error <= 1e-6)) {
    std::ostringstream s;
    s << "cut open along its boundary loops, the half's pieces make " << charts.num_charts
      << " charts with " << charts.flipped_faces
      << " pieces turned over and sides off their lengths by " << charts.max_relative_length_error;
    throw LayoutError(s.str());
  }
  std::vector<std::array<Eigen::Vector3d, 3>> corners(delivered.num_faces());
  for (int f = 0; f < delivered.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      corners[f][c] = Eigen::Vector3d(charts.corners[f][c].x(), charts.corners[f][c].y(), 0);
    }
  }
  return corners;
}

}  // namespace

std::string flow_on_double(const CompactMesh& half, const UniformizationOptions& o, int outer,
                           const TargetCurvature& target, Uniformization& run) {
  const CompactMesh twice = CompactMesh::doubled(half);
  const TargetCurvature twice_target = doubled_target(half, twice, target);
  const ConformalStructure structure = prepare_flow(twice, run.geometry, o.scheme, twice_target);
  FlowOptions flow = o.flow;
  flow.edge_flips = EdgeFlips::Always;  // the half's flow has shown that flips are needed
  // In the class the options ask for, by default the canonical one (that of the input metric's
  // intrinsic Delaunay triangulation), as on closed surfaces: the metric and its u are the
  // double's, so the halves stay mirror images. In the input triangulation's class the flat
  // metric at u = 0 is not the input's where faces are not Delaunay: the atlas's D, measured on
  // the pieces, suffered (sumo-tram.obj's parts of 26 boundary loops: pieces of faces of 140 to
  // 160 degrees drawn at twice their area, D 0.13 with u within 0.02 of 0), and so did the maps'
  // conformality (dart-drchubo-lhr.stl's disk: QC p95 2.36 there, 1.05 in the canonical class).
  RicciFlowSolver solver(twice, structure, flow);
  // An atlas draws its charts' insides again, harmonic: round pieces (texture_atlas.cpp).
  const PieceTriangles triangles = run.preset == TargetPreset::Atlas
                                       ? PieceTriangles::Roundest
                                       : PieceTriangles::NearestToConformal;

  Uniformization on_double;  // its totals are the double's flows only
  std::optional<HalfSubdivision> last;
  try {
    if (run.preset == TargetPreset::UnitDisk) {
      // Each flow's boundary lengths without its common subdivision, which is made once, for the
      // last (FreeSurfer's flat patch of a hemisphere: 15 flows, 1.1 s of subdivisions).
      const BoundaryRefit refit = [&](const FlowResult& r) {
        std::vector<double> lengths = boundary_lengths_on_double(half, twice, r);
        last.reset();
        if (lengths.empty()) {
          last = subdivide_half(half, twice, structure, r, triangles);
          lengths = last->boundary_lengths;
        }
        return doubled_target(half, twice, circle_boundary_target(half, lengths, outer));
      };
      fit_boundary_to_circles(solver, twice, refit, twice_target, o, on_double);
    } else {
      on_double.result = solver.solve(twice_target);
      on_double.totals.add(on_double.result);
    }
    if (on_double.result.converged && !last) {
      last = subdivide_half(half, twice, structure, on_double.result, triangles);
    }
  } catch (const LayoutError& e) {
    return "on the surface doubled along its boundary the flow converged, but " +
           std::string(e.what());
  }
  run.totals.add(on_double.totals);
  if (!on_double.result.converged) {
    std::ostringstream s;
    s << "on the surface doubled along its boundary, where boundary edges flip too, the flow "
         "stopped as well: "
      << on_double.result.failure;
    const Eigen::VectorXd& u = on_double.result.u;
    const double squeeze = u.size() ? std::exp(-(u.maxCoeff() - u.minCoeff()) / 2) : 1;
    if (squeeze < 1e-6) {
      s << " (by then lengths in one part were " << squeeze
        << " times those in another: the map squeezes part of the surface below what double "
           "precision resolves, as a long protrusion mapped onto a disk is"
        << (run.geometry == Geometry::Euclidean
                ? "; --target free-boundary keeps the boundary's lengths)"
                : ")");
    }
    return s.str();
  }

  const bool cut_open = run.geometry == Geometry::Euclidean && run.preset != TargetPreset::Atlas &&
                        planned_layout(half, run.preset, run.geometry) == LayoutKind::PlaneCut;
  std::vector<std::array<Eigen::Vector3d, 3>> cut_corners;
  CutGraph cut;
  if (cut_open) {
    try {
      cut_corners = cut_open_pieces(half, *last, cut);
    } catch (const LayoutError& e) {
      return "on the surface doubled along its boundary the flow converged, but " +
             std::string(e.what());
    }
  }
  run.doubled = true;
  run.doubled_because = run.result.failure;
  // With u held on the boundary its vertices keep their scale, but where the double's flips
  // cross it the boundary between them is the canonical metric's geodesic, of another length.
  bool boundary_held = !half.is_closed();
  for (int v = 0; v < half.num_vertices(); ++v) {
    if (half.is_boundary_vertex(v) && !target.is_fixed(v)) boundary_held = false;
  }
  if (run.geometry == Geometry::Euclidean && run.preset != TargetPreset::Atlas && boundary_held &&
      !last->boundary_lengths.empty()) {
    double input = 0, delivered = 0;
    for (int e = 0; e < half.num_edges(); ++e) {
      if (!half.is_boundary_edge(e)) continue;
      input += half.input_lengths()[e];
      delivered += last->boundary_lengths[e];
    }
    std::ostringstream s;
    s << "; with u held at the boundary's vertices the boundary is " << delivered / input
      << " times its input length in this class";
    run.doubled_because += s.str();
  }
  run.result = half_result(half, on_double.result);
  run.boundary_change = on_double.boundary_change;
  // u of the half is measured from the double's scaled input (H2 scales to the area of the
  // double's hyperbolic metric): the half's structure at that scale.
  run.structure = initialize_scheme(half, run.geometry, o.scheme, structure.length_scale);
  run.layout = Layout{};
  run.layout.geometry = run.geometry;
  run.layout.closure_error = last->closure_error;
  run.layout.max_relative_length_error = std::nan("");  // of the flow's triangles: not laid out
  CommonSubdivision& sub = last->subdivision;
  if (run.geometry == Geometry::Hyperbolic) {
    // Cut open where the development did not cross: the subdivision, with positions per corner
    // (the cut's deck transformations and relation error are not computed for it).
    run.layout_kind = LayoutKind::PoincareDisk;
    run.layout.relation_error = std::nan("");
    run.layout.reach = last->charts.reach;
    if (!last->charts.chart.empty()) {
      run.layout.chart = std::move(last->charts.chart);
      run.layout.chart_parent = std::move(last->charts.chart_parent);
      run.layout.chart_from_parent = std::move(last->charts.chart_from_parent);
      run.layout.chart_radius = last->charts.chart_radius;
    }
    run.layout.corners = sub.corners;
    run.subdivision = std::move(sub);
    return {};
  }
  if (run.preset == TargetPreset::Atlas) {
    // The atlas's charts are laid out from the pieces' own shapes: around a cone the development
    // does not close, and the mean of a vertex's corners there turned pieces over (sumo-tram's
    // atlas: 16 pieces, some with a side of 0.01 against 2.3 drawn half that off its line).
    sub.corners = std::move(last->piece_corners);
    run.subdivision = std::move(sub);
    return {};
  }
  if (cut_open) {
    // The cut is the delivered pieces' (its paths and generators as the report counts them); no
    // deck transformations are computed, and the per-vertex development's closure error, which
    // does not close around a loop, is not this layout's.
    run.layout_kind = LayoutKind::PlaneCut;
    run.layout.cut = std::move(cut);
    run.layout.closure_error = std::nan("");
    run.layout.relation_error = std::nan("");
    sub.corners = std::move(cut_corners);
    run.layout.corners = sub.corners;
    run.subdivision = std::move(sub);
    return {};
  }
  run.layout_kind = LayoutKind::Plane;
  // The half's own faces drawn by their corners: delivered instead when none turns over and they
  // are about as conformal as the pieces (pieces_more_conformal).
  std::vector<std::array<Eigen::Vector3d, 3>> own(half.num_faces());
  for (int f = 0; f < half.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) own[f][c] = sub.vertex_layout[half.face_vertex(f, c)];
    run.input_faces_turned_over += !(orientation(Geometry::Euclidean, own[f]) > 0);
  }
  if (o.keep_input_triangulation ||
      (run.input_faces_turned_over == 0 && !pieces_more_conformal(half, own, sub, run))) {
    run.position.assign(sub.vertex_layout.begin(), sub.vertex_layout.begin() + half.num_vertices());
  } else {
    run.position = sub.vertex_layout;
    run.layout.corners = sub.corners;
    run.subdivision = std::move(sub);
  }
  return {};
}

}  // namespace ricci::detail
