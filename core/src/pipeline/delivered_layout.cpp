#include "pipeline/delivered_layout.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <optional>
#include <sstream>

#include "layout/corners.h"
#include "pipeline/circle_domain.h"
#include "pipeline/disk_drawing.h"
#include "ricci/layout/lay_out.h"
#include "ricci/mesh/errors.h"
#include "ricci/pipeline/layout_quality.h"

namespace ricci::detail {

namespace {

// Flat torus: the deck translations are sums of two generators; the most independent pair spans
// them.
std::vector<std::complex<double>> torus_periods(const Layout& layout) {
  std::vector<std::complex<double>> periods;
  double best = 0;
  for (const DiskIsometry& a : layout.deck) {
    for (const DiskIsometry& b : layout.deck) {
      const double cross = std::abs(std::imag(std::conj(a.b) * b.b));
      if (cross > best) best = cross, periods = {a.b, b.b};
    }
  }
  return periods;
}

// The common subdivision of the flipped triangulation, where the input's own faces drawn by
// their corners turn none over but are farther from conformal than its pieces.
std::optional<CommonSubdivision> more_conformal_pieces(
    const CompactMesh& mesh, const std::vector<std::array<Eigen::Vector3d, 3>>& corners,
    Uniformization& run) {
  try {
    CommonSubdivision pieces = common_subdivision(mesh, run.structure, run.result, run.layout);
    if (pieces_more_conformal(mesh, corners, pieces, run)) return pieces;
  } catch (const LayoutError&) {
    // The input's own faces stay: they are a map.
  }
  return std::nullopt;
}

}  // namespace

// Flips happened and none of the input's faces turns over when drawn by its corners: that
// drawing is a map, but not the discrete conformal map, which is projective on the pieces of the
// input and final triangulations cut together. The input's own faces are kept where they are
// about as conformal as the pieces (QC p95 at most this factor above theirs), or where the pieces
// would add faces collapsed below double precision; else the pieces. gltron-recognizer-quad.obj's
// disk with u = 0 on its boundary (74 flips): 44 faces of QC p95 26.3, 246 pieces of 7.24 (CEPS:
// 6.0); sumo-tram.obj's two 112-face parts: 9.57 against 3.83.
constexpr double kOwnFacesQcAllowance = 1.1;

bool pieces_more_conformal(const CompactMesh& mesh,
                           const std::vector<std::array<Eigen::Vector3d, 3>>& corners,
                           const CommonSubdivision& pieces, Uniformization& run) {
  const LayoutQuality own = measure_layout(mesh, run.geometry, run.result, corners);
  const LayoutQuality cut = measure_layout(face_sides(pieces.positions, pieces.faces), run.geometry,
                                           run.result, pieces.corners);
  if (own.quasi_conformal_p95 > kOwnFacesQcAllowance * cut.quasi_conformal_p95 &&
      cut.collapsed_faces <= own.collapsed_faces && cut.flipped_faces == 0) {
    run.input_faces_qc_p95 = own.quasi_conformal_p95;
    return true;
  }
  return false;
}

// The delivered mesh's positions and corners from the layout's (`position` per vertex of the
// delivered mesh for per-vertex layouts, `corners` per input face otherwise): the sphere centred,
// the unit disk normalized.
void place_delivered(const CompactMesh& mesh, const UniformizationOptions& o, int outer_loop,
                     std::vector<Eigen::Vector3d> position,
                     std::vector<std::array<Eigen::Vector3d, 3>> corners, Uniformization& run) {
  const CommonSubdivision* sub = run.subdivision ? &*run.subdivision : nullptr;
  const bool per_vertex =
      run.layout_kind == LayoutKind::Plane || run.layout_kind == LayoutKind::Sphere;
  if (run.layout_kind == LayoutKind::Sphere && mesh.is_closed()) {
    // The centring Moebius map moves vertices along circles, not the faces' chords: a large thin
    // face of a coarse mesh can turn over. The sphere stays uncentred then.
    std::vector<Eigen::Vector3d> centred = center_on_sphere(position, mesh.num_vertices());
    const std::vector<std::array<int, 3>>& faces = sub ? sub->faces : mesh.faces();
    auto turned = [&](const std::vector<Eigen::Vector3d>& p) {
      int n = 0;
      for (const auto& t : faces)
        n += !(orientation(run.geometry, {p[t[0]], p[t[1]], p[t[2]]}) > 0);
      return n;
    };
    if (turned(centred) <= turned(position)) {
      position = std::move(centred);
    } else {
      run.centring_skipped = true;
    }
  }
  if (run.preset == TargetPreset::UnitDisk) {
    position = detail::normalize_to_unit_disk(
        std::move(position), mesh.boundary_loops()[outer_loop], o.center_vertex, o.axis_vertex);
    run.circle_error = detail::circle_error(position, mesh);
  }
  run.position = std::move(position);
  if (!sub) {
    if (per_vertex) {
      corners.resize(mesh.num_faces());
      for (int f = 0; f < mesh.num_faces(); ++f) {
        for (int c = 0; c < 3; ++c) corners[f][c] = run.position[mesh.face_vertex(f, c)];
      }
    } else {
      weld_corner_copies(mesh.faces(), corners);
    }
    run.corners = std::move(corners);
    return;
  }
  if (!per_vertex) {
    run.corners = sub->corners;
    weld_corner_copies(sub->faces, run.corners);
    run.model_corners = sub->model_corners;
    if (!run.model_corners.empty()) weld_corner_copies(sub->faces, run.model_corners);
    return;
  }
  run.corners.resize(sub->faces.size());
  for (size_t f = 0; f < sub->faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) run.corners[f][c] = run.position[sub->faces[f][c]];
  }
}

// The layout of a converged flow, its per-vertex positions where it has them, and the corners of
// the delivered faces: the input's, or, when those would turn over after edge flips, the common
// subdivision's. H2 charts of `chart_radius`.
void lay_out_result(const CompactMesh& mesh, const UniformizationOptions& o, int outer_loop,
                    double chart_radius, Uniformization& run) {
  const Triangulation& flowed = result_triangulation(mesh, run.result);
  run.layout_kind = planned_layout(mesh, run.preset, run.geometry);
  run.layout =
      lay_out(flowed, run.geometry, run.result.edge_lengths, o.flow.linear_solver, chart_radius);
  run.input_faces_turned_over = 0;
  run.input_faces_qc_p95 = std::numeric_limits<double>::quiet_NaN();
  run.subdivision.reset();
  run.subdivision_failure.clear();
  run.face_chart.clear();
  const bool per_vertex =
      run.layout_kind == LayoutKind::Plane || run.layout_kind == LayoutKind::Sphere;
  std::vector<Eigen::Vector3d> position;
  if (per_vertex) position = vertex_positions(flowed, run.layout);
  if (run.geometry == Geometry::Euclidean && mesh.is_closed() && mesh.genus() == 1) {
    run.periods = torus_periods(run.layout);
  }
  if (run.layout_kind == LayoutKind::None) return;
  std::vector<std::array<Eigen::Vector3d, 3>> corners;
  if (per_vertex) {
    corners.resize(mesh.num_faces());
    for (int f = 0; f < mesh.num_faces(); ++f) {
      for (int c = 0; c < 3; ++c) corners[f][c] = position[mesh.face_vertex(f, c)];
    }
  } else {
    corners = corners_on(flowed, run.layout, mesh);
  }
  // The normalizations below keep orientations: count the turned faces before them.
  if (!run.result.flip_sequence.empty()) {
    for (const auto& t : corners) {
      run.input_faces_turned_over += !(orientation(run.geometry, t) > 0);
    }
  }
  if (run.input_faces_turned_over > 0 && !o.keep_input_triangulation) {
    try {
      run.subdivision = common_subdivision(mesh, run.structure, run.result, run.layout);
    } catch (const LayoutError& e) {
      run.subdivision_failure = e.what();
    }
  } else if (!run.result.flip_sequence.empty() && !o.keep_input_triangulation &&
             run.layout.num_charts() <= 1) {
    run.subdivision = more_conformal_pieces(mesh, corners, run);
  }
  // The input as a subdivision of itself (no flips), or cut along the flipped triangulation.
  const auto deliver_subdivision = [&] {
    if (run.subdivision || !run.subdivision_failure.empty()) return;
    try {
      run.subdivision = run.result.flip_sequence.empty()
                            ? detail::input_as_subdivision(mesh, run.result, corners)
                            : common_subdivision(mesh, run.structure, run.result, run.layout);
    } catch (const LayoutError& e) {
      run.subdivision_failure = e.what();
    }
  };
  // A layout in several charts is delivered as a subdivision, each face in one chart (input faces
  // drawn over flipped faces could straddle two).
  if (run.layout.num_charts() > 1 &&
      !(o.keep_input_triangulation && !run.result.flip_sequence.empty())) {
    deliver_subdivision();
  }
  // Thin faces near the Poincare disk's rim that turn over only as drawn (straight) are split.
  if (run.layout_kind == LayoutKind::PoincareDisk && !o.keep_input_triangulation &&
      detail::has_drawing_turned_faces(run.subdivision ? run.subdivision->corners : corners)) {
    deliver_subdivision();
    std::optional<CommonSubdivision> on_geodesics;
    if (run.subdivision) {
      if (run.subdivision->num_flips > 0) on_geodesics = *run.subdivision;
      run.subdivision->disk_splits = detail::split_turned_disk_faces(mesh, *run.subdivision);
    }
    // Where splitting the geodesic pieces leaves some turned as drawn (openscad-tardis.stl: one
    // of 14,804), the new vertices on the sides of their final faces go onto the sides as drawn,
    // and the splits run again; where that still leaves some (cura-zav-maxpro.stl: genus 97,
    // 80k flips), every new vertex does. That drawing is the texture's (`corners`); the model's
    // corners keep every vertex on the geodesics (`model_corners`), where the copies across the
    // cut glue.
    if (on_geodesics && detail::has_drawing_turned_faces(run.subdivision->corners)) {
      CommonSubdivision sub = std::move(*on_geodesics);
      sub.drawn_side_corners = detail::draw_sides_straight(
          sub, run.layout,
          detail::final_faces_turned_as_drawn(*run.subdivision,
                                              static_cast<int>(run.layout.corners.size())));
      sub.disk_splits = detail::split_turned_disk_faces(mesh, sub);
      run.subdivision = std::move(sub);
    }
    if (run.subdivision && run.subdivision->num_flips > 0 &&
        detail::has_drawing_turned_faces(run.subdivision->corners)) {
      try {
        CommonSubdivision drawn = common_subdivision(mesh, run.structure, run.result, run.layout,
                                                     DiskSidePoints::OnDrawnSide);
        // The same pieces with their new vertices on the geodesics: the model's corners.
        const CommonSubdivision geodesic =
            common_subdivision(mesh, run.structure, run.result, run.layout);
        if (geodesic.faces != drawn.faces) {
          throw LayoutError(
              "common subdivision: the pieces drawn on straight sides differ from those on the "
              "geodesics");
        }
        drawn.model_corners = geodesic.corners;
        drawn.disk_splits = detail::split_turned_disk_faces(mesh, drawn);
        drawn.on_drawn_sides = true;
        run.subdivision = std::move(drawn);
      } catch (const LayoutError& e) {
        run.subdivision_failure = e.what();
      }
    }
  }
  const CommonSubdivision* sub = run.subdivision ? &*run.subdivision : nullptr;
  if (run.layout.num_charts() > 1 && sub) {
    for (int f : sub->final_face) run.face_chart.push_back(run.layout.chart[f]);
  }
  if (sub && per_vertex) {
    position.insert(position.end(), sub->vertex_layout.begin() + mesh.num_vertices(),
                    sub->vertex_layout.end());
  }
  place_delivered(mesh, o, outer_loop, std::move(position), std::move(corners), run);
}

// What makes a converged layout no map: faces turned over, the unit disk's loops off circles.
std::string layout_failure(const Uniformization& run) {
  std::ostringstream s;
  if (run.layout.num_charts() > 1 && run.face_chart.empty()) {
    s << "the Poincare disk layout needs " << run.layout.num_charts()
      << " charts (the domain reaches hyperbolic distance " << run.layout.reach
      << "), and the input's faces over the flipped triangulation cannot be drawn in them";
    if (!run.subdivision_failure.empty()) {
      s << " (the common subdivision could not be built: " << run.subdivision_failure << ")";
    } else {
      s << " (--keep-input-triangulation)";
    }
    return s.str();
  }
  if (run.subdivision && run.quality.flipped_faces > 0) {
    s << run.quality.flipped_faces << " faces of the delivered subdivision are turned over (first: "
      << "face " << run.quality.first_flipped_face << ")";
    return s.str();
  }
  if (run.quality.flipped_faces > 0) {
    s << run.quality.flipped_faces << " of the input's faces are turned over (first: face "
      << run.quality.first_flipped_face << ")";
    if (run.totals.edge_flips > 0) {
      s << ": the flow needed edge flips, and the input's faces drawn over the flipped "
           "triangulation by their corners turn over";
      if (!run.subdivision_failure.empty()) {
        s << "; the common subdivision could not be built (" << run.subdivision_failure << ")";
      }
    }
    return s.str();
  }
  if (run.preset == TargetPreset::UnitDisk && !(run.circle_error <= 1e-6)) {
    s << "the boundary loops are not on circles: circle error " << run.circle_error;
    if (run.quality.collapsed_faces > 0) {
      s << "; " << run.quality.collapsed_faces
        << " faces are squeezed below 1e-12 of the mean area, so loops far down a tube shrink "
           "below what double precision resolves (the conformal map of a long tube onto a "
           "circle domain is exponentially small there); --target free-boundary keeps the "
           "boundary's lengths";
    } else {
      s << " (a flat metric with these boundary curvatures was found, but its loops do not "
           "close up into circles)";
    }
  }
  return s.str();
}

}  // namespace ricci::detail
