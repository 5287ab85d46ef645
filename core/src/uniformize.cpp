#include "ricci/uniformize.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>

#include "circle_domain.h"
#include "disk_drawing.h"
#include "doubled_surface.h"
#include "ricci/errors.h"
#include "spherical_start.h"

namespace ricci {

namespace {

void check_request(const CompactMesh& mesh, TargetPreset preset, Geometry geometry,
                   const UniformizationOptions& o) {
  const std::string topology = mesh.topology_name();
  if (preset == TargetPreset::UnitDisk) {
    if (mesh.is_closed() || mesh.genus() != 0) {
      throw InvalidTargetError(
          "the disk target maps a genus-0 surface with boundary to the unit "
          "disk, but the mesh is a " +
          topology + "; use the auto target (it picks the metric for this topology)");
    }
    if (geometry != Geometry::Euclidean) {
      throw InvalidTargetError(
          "the disk target is a euclidean layout; choose euclidean (or "
          "auto) geometry instead of " +
          to_string(geometry));
    }
  }
  if (preset == TargetPreset::FreeBoundary && mesh.is_closed()) {
    throw InvalidTargetError("the free-boundary target needs a boundary, but the mesh is a " +
                             topology + "; use the zero or auto target");
  }
  for (const auto& [vertex, name] :
       {std::pair{o.center_vertex, "center"}, std::pair{o.axis_vertex, "axis"}}) {
    if (vertex < 0) continue;
    if (preset != TargetPreset::UnitDisk) {
      throw InvalidArgumentError(std::string("the ") + name +
                                 " vertex normalizes the unit disk map; it needs the disk target");
    }
    if (vertex >= mesh.num_vertices()) {
      throw InvalidArgumentError(std::string("the ") + name + " vertex " + std::to_string(vertex) +
                                 " is out of range: the mesh has vertices "
                                 "0.." +
                                 std::to_string(mesh.num_vertices() - 1));
    }
  }
  if (o.center_vertex >= 0 && mesh.is_boundary_vertex(o.center_vertex)) {
    throw InvalidArgumentError("the center vertex " + std::to_string(o.center_vertex) +
                               " lies on the boundary, which maps to the unit circle; choose an "
                               "interior vertex");
  }
  if (o.center_vertex >= 0 && o.center_vertex == o.axis_vertex) {
    throw InvalidArgumentError("the axis vertex must differ from the center vertex");
  }
}

// Cones as the Values preset's per-vertex curvature.
UniformizationOptions with_cone_values(const CompactMesh& mesh, UniformizationOptions o) {
  if (o.cones.empty()) return o;
  o.preset = TargetPreset::Values;
  o.values = cone_target(mesh, o.cones).values();
  o.cones.clear();
  return o;
}

// The preset's target before any flow (the disk preset's is refitted by the flows).
TargetCurvature initial_target(const CompactMesh& mesh, TargetPreset preset,
                               const UniformizationOptions& o, int outer_loop) {
  switch (preset) {
    case TargetPreset::UnitDisk:
      return circle_boundary_target(mesh, mesh.input_lengths(), outer_loop);
    case TargetPreset::FreeBoundary:
      return TargetCurvature::free_boundary(mesh);
    case TargetPreset::Values:
      return TargetCurvature::from_values(mesh, o.values);
    default:
      return TargetCurvature::zero(mesh);
  }
}

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
    }
    run.corners = std::move(corners);
    return;
  }
  if (!per_vertex) {
    run.corners = sub->corners;
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
    if (run.subdivision) {
      run.subdivision->disk_splits = detail::split_turned_disk_faces(mesh, *run.subdivision);
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

}  // namespace

void FlowTotals::add(const FlowResult& r) {
  FlowTotals one;
  if (r.flips_from_iteration >= 0) {
    one.flips_from_iteration = r.flips_from_iteration;
    one.without_flips = r.without_flips;
  }
  one.attainable_residual = r.attainable_residual;
  one.flows = 1;
  one.newton_iterations = r.iterations;
  one.edge_flips = r.num_flips;
  one.symbolic_analyses = r.num_analyses;
  one.numeric_factorizations = r.num_factorizations;
  one.krylov_iterations = r.krylov_iterations;
  one.times = r.times;
  add(one);
}

void FlowTotals::add(const FlowTotals& o) {
  attainable_residual = std::max(attainable_residual, o.attainable_residual);
  if (flips_from_iteration < 0 && o.flips_from_iteration >= 0) {
    flips_from_iteration = newton_iterations + o.flips_from_iteration;
    without_flips = o.without_flips;
  }
  flows += o.flows;
  newton_iterations += o.newton_iterations;
  edge_flips += o.edge_flips;
  symbolic_analyses += o.symbolic_analyses;
  numeric_factorizations += o.numeric_factorizations;
  krylov_iterations += o.krylov_iterations;
  for (auto [to, from] : {std::pair{&times.setup, o.times.setup},
                          {&times.assembly, o.times.assembly},
                          {&times.analysis, o.times.analysis},
                          {&times.factorization, o.times.factorization},
                          {&times.solve, o.times.solve},
                          {&times.line_search, o.times.line_search},
                          {&times.flips, o.times.flips},
                          {&times.total, o.times.total}}) {
    *to += from;
  }
}

void Uniformization::require_valid(const std::string& subject) const {
  if (!result.converged) {
    throw ConvergenceError(flow_failure_message(geometry, scheme, result, subject),
                           result.iterations, result.residual);
  }
  if (!layout_failure.empty()) {
    throw LayoutError("layout" + (subject.empty() ? "" : " of " + subject) + ": " + layout_failure);
  }
}

std::string to_string(LayoutKind k) {
  switch (k) {
    case LayoutKind::None:
      return "none";
    case LayoutKind::Plane:
      return "plane";
    case LayoutKind::PlaneCut:
      return "plane-cut";
    case LayoutKind::PoincareDisk:
      return "poincare-disk";
    case LayoutKind::Sphere:
      return "sphere";
  }
  return "?";
}

std::vector<std::array<Eigen::Vector2d, 3>> drawn_corners(const Uniformization& run) {
  std::vector<std::array<Eigen::Vector2d, 3>> drawn;
  if (run.layout_kind == LayoutKind::None || run.layout_kind == LayoutKind::Sphere) return drawn;
  const int charts = run.face_chart.empty() ? 1 : run.layout.num_charts();
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(charts))));
  for (size_t f = 0; f < run.corners.size(); ++f) {
    const int k = run.face_chart.empty() ? 0 : run.face_chart[f];
    const Eigen::Vector2d offset(2.25 * (k % columns), -2.25 * (k / columns));
    std::array<Eigen::Vector2d, 3> t;
    for (int c = 0; c < 3; ++c) t[c] = run.corners[f][c].head<2>() + offset;
    drawn.push_back(t);
  }
  return drawn;
}

TextureCoordinates texture_coordinates(const Uniformization& run) {
  TextureCoordinates t;
  if (run.layout_kind == LayoutKind::Plane) {
    std::vector<Eigen::Vector2d> planar;
    for (const auto& p : run.position) planar.emplace_back(p.x(), p.y());
    t.vertex = normalized_texture_coordinates(planar);
  } else if (run.layout_kind == LayoutKind::PlaneCut ||
             run.layout_kind == LayoutKind::PoincareDisk) {
    std::vector<Eigen::Vector2d> flat;
    for (const auto& face : drawn_corners(run)) {
      for (const auto& p : face) flat.push_back(p);
    }
    if (run.layout_kind == LayoutKind::PlaneCut || !run.face_chart.empty()) {
      flat = normalized_texture_coordinates(flat);
    } else {
      for (auto& p : flat) p = (p + Eigen::Vector2d::Ones()) / 2;
    }
    t.wedge.resize(run.corners.size());
    for (size_t f = 0; f < run.corners.size(); ++f) {
      for (int c = 0; c < 3; ++c) t.wedge[f][c] = flat[3 * f + c];
    }
  }
  return t;
}

std::pair<TargetPreset, Geometry> resolve_request(const CompactMesh& mesh,
                                                  const UniformizationOptions& request) {
  const UniformizationOptions o = with_cone_values(mesh, request);
  TargetPreset preset = o.preset;
  Geometry geometry;
  if (preset == TargetPreset::Automatic) {
    const auto automatic = automatic_preset(mesh);
    preset = automatic.first;
    geometry = o.geometry.value_or(automatic.second);
  } else if (preset == TargetPreset::Values) {
    geometry = o.geometry.value_or(
        geometry_for_target(mesh, TargetCurvature::from_values(mesh, o.values)));
  } else {
    geometry = o.geometry.value_or(preset_geometry(mesh, preset));
  }
  check_request(mesh, preset, geometry, o);
  return {preset, geometry};
}

LayoutKind planned_layout(const Triangulation& mesh, TargetPreset preset, Geometry geometry) {
  switch (geometry) {
    case Geometry::Euclidean:
      if (mesh.is_disk() || preset == TargetPreset::UnitDisk) return LayoutKind::Plane;
      return LayoutKind::PlaneCut;
    case Geometry::Hyperbolic:
      return LayoutKind::PoincareDisk;
    case Geometry::Spherical:
      return mesh.genus() == 0 ? LayoutKind::Sphere : LayoutKind::None;
  }
  return LayoutKind::None;
}

namespace {

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

// The flow (the disk preset: by one solve when one_solve, else or where that does not converge by
// the fixed point of repeated flows; the double where the surface's own triangulation stalls at
// the boundary) and the layout of its result.
// Returns true when the result is the disk preset's one solve.
bool flow_and_lay_out(const CompactMesh& mesh, const UniformizationOptions& o, int outer,
                      const TargetCurvature& target, bool one_solve, Uniformization& run) {
  bool by_one_solve = false;
  {
    // Its factorizations are freed before the flow on the double and the layout, which need none.
    RicciFlowSolver solver(mesh, run.structure, o.flow, o.vertex_order);
    if (run.preset == TargetPreset::UnitDisk) {
      by_one_solve = detail::reach_circle_domain(solver, mesh, outer, target, o, one_solve, run);
    } else {
      const std::optional<Eigen::VectorXd> start =
          flow_start(mesh, run.structure, target, o.flow, o.vertex_order);
      run.result = solver.solve(target, start ? &*start : nullptr);
      run.totals.add(run.result);
    }
  }
  if (detail::may_flow_on_double(mesh, o, target, run)) {
    detail::flow_on_double(mesh, o, outer, target, run);
  }
  const auto measure = [&] {
    if (run.subdivision) {
      run.quality = measure_layout(face_sides(run.subdivision->positions, run.subdivision->faces),
                                   run.geometry, run.result, run.corners);
    } else {
      run.quality = measure_layout(mesh, run.geometry, run.result, run.corners);
    }
  };
  if (run.doubled) {
    place_delivered(mesh, o, outer, std::move(run.position), {}, run);
  } else if (run.result.converged) {
    lay_out_result(mesh, o, outer, kChartRadius, run);
  }
  measure();
  // H2 in charts: the common subdivision of many flips has pieces far thinner than the flowed
  // faces, which can turn over near a chart's rim (cura-zav-maxpro.stl, genus 97, 80k flips:
  // 2116 at radius 12, none at 6). Smaller charts keep them farther from it.
  for (double radius = kChartRadius / 2;
       radius >= kChartRadius / 4 && !run.doubled && !o.keep_input_triangulation &&
       run.quality.flipped_faces > 0 && run.layout.num_charts() > 1;
       radius /= 2) {
    lay_out_result(mesh, o, outer, radius, run);
    measure();
  }
  if (run.result.converged) run.layout_failure = layout_failure(run);
  return by_one_solve;
}

// The run for the preset resolved from the request.
Uniformization uniformize_as_requested(const CompactMesh& mesh,
                                       const UniformizationOptions& request) {
  const UniformizationOptions o = with_cone_values(mesh, request);
  Uniformization run;
  std::tie(run.preset, run.geometry) = resolve_request(mesh, o);
  run.scheme = o.scheme.scheme;
  run.tolerance = o.flow.tolerance;
  const int outer =
      run.preset == TargetPreset::UnitDisk ? outer_boundary_loop(mesh, mesh.input_lengths()) : -1;
  const TargetCurvature target = initial_target(mesh, run.preset, o, outer);
  run.structure = prepare_flow(mesh, run.geometry, o.scheme, target);
  const bool one_solve = run.preset == TargetPreset::UnitDisk &&
                         run.geometry == Geometry::Euclidean && is_yamabe(run.structure);
  const Uniformization start = run;
  const bool by_one_solve = flow_and_lay_out(mesh, o, outer, target, one_solve, run);
  // The one solve leaves the disk's Moebius maps free, and can end at one that squeezes most of
  // the surface below what double precision lays out (pymeshlab's face scan: u from -65 to 4.6,
  // the circles lost); the repeated flows, each with a boundary target held fixed, end near the
  // input's own proportions.
  if (by_one_solve && run.result.converged && !run.layout_failure.empty()) {
    Uniformization again = start;
    again.totals = run.totals;
    flow_and_lay_out(mesh, o, outer, target, false, again);
    return again;
  }
  return run;
}

// A request the automatic target answers as best it can: no cones, centre or axis.
bool best_effort(const UniformizationOptions& request) {
  return request.preset == TargetPreset::Automatic && request.cones.empty() &&
         request.center_vertex < 0 && request.axis_vertex < 0;
}

// What an attempt that is not delivered adds to the cost (flows, iterations, factorizations,
// times); its edge flips and convergence floor are not the delivered run's.
FlowTotals cost_of(const FlowTotals& attempt) {
  FlowTotals cost = attempt;
  cost.edge_flips = 0;
  cost.flips_from_iteration = -1;
  cost.without_flips.clear();
  cost.attainable_residual = 0;
  return cost;
}

// `instead`, delivered in place of `attempt`, whose cost counts before its own.
Uniformization delivered_instead(const Uniformization& attempt, Uniformization instead) {
  FlowTotals totals = cost_of(attempt.totals);
  totals.add(instead.totals);
  instead.totals = totals;
  return instead;
}

// Why a run is not valid.
std::string why_not_valid(const Uniformization& run) {
  return run.converged() ? "gave no map: " + run.layout_failure
                         : "was not reached: " + run.result.failure;
}

// The requested preset, and for the automatic target where the circle domain fails, the free
// boundary; where that fails too, `free_failure` says why.
Uniformization uniformize_by_target(const CompactMesh& mesh, const UniformizationOptions& request,
                                    std::string& free_failure) {
  Uniformization run = uniformize_as_requested(mesh, request);
  // The automatic target asks for a map, not a circle domain at any price: where the circle
  // domain is not reached (its boundary does not settle) or its layout is no map (it squeezes
  // faces below what double precision draws, loops far down a tube), the free boundary, which
  // keeps the boundary's lengths.
  const bool circles_failed = run.preset == TargetPreset::UnitDisk &&
                              run.result.stop != FlowStop::Cancelled && !run.valid();
  if (!best_effort(request) || !circles_failed) return run;
  UniformizationOptions free = request;
  free.preset = TargetPreset::FreeBoundary;
  Uniformization instead = uniformize_as_requested(mesh, free);
  if (instead.result.stop == FlowStop::Cancelled) return instead;
  if (!instead.valid()) {
    run.totals.add(cost_of(instead.totals));
    free_failure = "the free-boundary target, tried instead, " + why_not_valid(instead);
    return run;
  }
  std::ostringstream why;
  if (!run.converged()) {
    why << "the circle domain was not reached: " << run.result.failure;
  } else if (run.quality.collapsed_faces > 0) {
    why << "the circle domain squeezes " << run.quality.collapsed_faces
        << " faces below 1e-12 of the mean area (circle error " << run.circle_error
        << "): loops far down a tube shrink below what double precision resolves";
  } else {
    why << "the circle domain's layout is no map: " << run.layout_failure;
  }
  instead = delivered_instead(run, std::move(instead));
  instead.target_instead = why.str();
  return instead;
}

}  // namespace

Uniformization uniformize(const CompactMesh& mesh, const UniformizationOptions& request) {
  std::string free_failure;
  Uniformization run = uniformize_by_target(mesh, request, free_failure);
  // The automatic target with the Yamabe scheme, where it gives no map (for a circle domain:
  // neither it nor the free boundary): the tangential scheme, whose triangles are valid at every
  // u (sumo-tram.obj's windowed body: boundary vertices of one triangle that a circle domain needs
  // above 180 degrees, stalled on the surface and on its double, and a free boundary whose
  // boundary triangles degenerate). Not where the request holds the Yamabe flow to the input's
  // triangulation or asks for the input's faces as laid out.
  const bool yamabe_best_effort = best_effort(request) && request.scheme.scheme == Scheme::Yamabe &&
                                  request.flow.edge_flips != EdgeFlips::Never &&
                                  !request.keep_input_triangulation;
  if (!yamabe_best_effort || run.valid() || run.result.stop == FlowStop::Cancelled) return run;
  UniformizationOptions tangential = request;
  tangential.scheme = SchemeOptions();
  tangential.scheme.scheme = Scheme::Tangential;
  std::string tangential_free_failure;
  Uniformization instead = uniformize_by_target(mesh, tangential, tangential_free_failure);
  std::string why =
      "with the Yamabe scheme the " + to_string(run.preset) + " target " + why_not_valid(run);
  if (!free_failure.empty()) why += "; " + free_failure;
  if (!instead.valid() && instead.result.stop != FlowStop::Cancelled) {
    // The Yamabe run's failure, and that the tangential scheme was tried.
    std::string& failure = run.converged() ? run.layout_failure : run.result.failure;
    if (!free_failure.empty()) failure += "; " + free_failure;
    failure += "; the tangential scheme, tried instead, " + why_not_valid(instead);
    run.totals.add(cost_of(instead.totals));
    return run;
  }
  instead = delivered_instead(run, std::move(instead));
  instead.scheme_instead = why;
  return instead;
}

}  // namespace ricci
