#include "ricci/pipeline/uniformize.h"

#include <cmath>
#include <exception>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>

#include "flow/spherical_start.h"
#include "mesh/clock.h"
#include "pipeline/attempts.h"
#include "pipeline/circle_domain.h"
#include "pipeline/delivered_layout.h"
#include "pipeline/disk_drawing.h"
#include "pipeline/doubled_surface.h"
#include "pipeline/texture_atlas.h"
#include "ricci/flow/ricci_flow.h"
#include "ricci/layout/packing.h"
#include "ricci/mesh/errors.h"

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
  if (preset == TargetPreset::Atlas &&
      (geometry != Geometry::Euclidean || o.scheme.scheme != Scheme::Yamabe)) {
    throw InvalidTargetError(
        "the atlas target is a flat cone metric of the Yamabe flow; choose euclidean (or auto) "
        "geometry and the yamabe scheme");
  }
  // Its charts are packed after every flow and layout: options that cannot pack, refused first.
  if (preset == TargetPreset::Atlas) check_packing_options(o.packing);
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

// An interior vertex whose cone angle is within this of 2 pi (radians) is flat: 359.9999999
// degrees, or an angle read back from a report's radians.
constexpr double kFlatCone = 1e-9;

// Curvature prescribed at an interior vertex (a cone) is refused by the Values preset: the plane,
// disk and sphere layouts draw the surface around each interior vertex in one piece, which a
// cone's angle does not close (a torus with two cones came back "flat" with a closure error of
// 2.3, a sphere with eight with 124 faces turned); the atlas cuts its seams through them.
bool interior_cone(const CompactMesh& mesh, const TargetCurvature& target, int v) {
  return !mesh.is_boundary_vertex(v) && !target.fixed[v] &&
         std::abs(target.curvature[v]) > kFlatCone;
}
// Vertex v as the user numbers it (UniformizationOptions::input_vertex).
int user_vertex(const UniformizationOptions& o, int v) {
  return o.input_vertex.empty() ? v : o.input_vertex[static_cast<size_t>(v)];
}
constexpr const char* kNoConeInOnePiece =
    " inside the surface; a layout in one piece cannot draw a cone inside it: --target atlas "
    "--cones FILE cuts seams through the cones and lays out the charts";

// Cones as the Values preset's per-vertex curvature, on the boundary only (interior_cone).
UniformizationOptions with_cone_values(const CompactMesh& mesh, UniformizationOptions o) {
  if (o.cones.empty() || o.preset == TargetPreset::Atlas) return o;
  const TargetCurvature cones = cone_target(mesh, o.cones);  // checks the vertices and angles
  for (const Cone& c : o.cones) {
    if (interior_cone(mesh, cones, c.vertex)) {
      std::ostringstream s;
      s.precision(10);
      s << "cone at vertex " << user_vertex(o, c.vertex) << ": " << c.angle * 180 / kPi
        << " degrees" << kNoConeInOnePiece;
      throw InvalidTargetError(s.str());
    }
  }
  o.preset = TargetPreset::Values;
  o.values = cones.values();
  o.cones.clear();
  return o;
}

// The preset's target before any flow (the disk preset's is refitted by the flows).
TargetCurvature initial_target(const CompactMesh& mesh, TargetPreset preset,
                               const UniformizationOptions& o, int outer_loop,
                               const ConePlacement& placement) {
  switch (preset) {
    case TargetPreset::Atlas:
      return detail::atlas_target(mesh, placement,
                                  o.cone_placement.quarter_angles || !o.cones.empty());
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

}  // namespace

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
    const TargetCurvature target = TargetCurvature::from_values(mesh, o.values);
    geometry = o.geometry.value_or(geometry_for_target(mesh, target));
    // (Where no layout is drawn, S2 on a surface of genus > 0, the metric alone is given.)
    const bool laid_out = planned_layout(mesh, preset, geometry) != LayoutKind::None;
    for (int v = 0; laid_out && v < mesh.num_vertices(); ++v) {
      // (Kbar >= 2 pi is no cone: the target's checks say so.)
      if (interior_cone(mesh, target, v) && target.curvature[v] < 2 * kPi) {
        std::ostringstream s;
        s.precision(10);
        s << "target curvature at vertex " << user_vertex(o, v) << ": " << target.curvature[v]
          << " (a cone of " << (2 * kPi - target.curvature[v]) * 180 / kPi << " degrees)"
          << kNoConeInOnePiece;
        throw InvalidTargetError(s.str());
      }
    }
  } else {
    geometry = o.geometry.value_or(preset_geometry(mesh, preset));
  }
  check_request(mesh, preset, geometry, o);
  return {preset, geometry};
}

namespace {

// The layout of a flow's result (on the double: of the half's pieces), its quality, and why it
// is no valid map.
void lay_out_flow(const CompactMesh& mesh, const UniformizationOptions& o, int outer,
                  Uniformization& run) {
  const auto measure = [&] {
    if (run.subdivision) {
      run.quality = measure_layout(face_sides(run.subdivision->positions, run.subdivision->faces),
                                   run.geometry, run.result, run.corners);
    } else {
      run.quality = measure_layout(mesh, run.geometry, run.result, run.corners);
    }
  };
  if (run.doubled && run.preset == TargetPreset::Atlas) {
    detail::lay_out_atlas(mesh, o, run);
  } else if (run.doubled) {
    // Thin faces near the Poincare disk's rim that turn over only as drawn (straight) are split.
    if (run.layout_kind == LayoutKind::PoincareDisk && !o.keep_input_triangulation &&
        detail::has_drawing_turned_faces(run.subdivision->corners)) {
      run.subdivision->disk_splits = detail::split_turned_disk_faces(mesh, *run.subdivision);
    }
    if (run.subdivision) run.face_chart = run.subdivision->chart;
    detail::place_delivered(mesh, o, outer, std::move(run.position), {}, run);
  } else if (run.result.converged && run.preset == TargetPreset::Atlas) {
    detail::lay_out_atlas(mesh, o, run);
  } else if (run.result.converged) {
    detail::lay_out_result(mesh, o, outer, kChartRadius, run);
  }
  measure();
  // H2 in charts: the common subdivision of many flips has pieces far thinner than the flowed
  // faces, which can turn over near a chart's rim (cura-zav-maxpro.stl, genus 97, 80k flips:
  // 2116 at radius 12, none at 6). Smaller charts keep them farther from it.
  for (double radius = kChartRadius / 2;
       radius >= kChartRadius / 4 && !run.doubled && !o.keep_input_triangulation &&
       run.quality.flipped_faces > 0 && run.layout.num_charts() > 1;
       radius /= 2) {
    detail::lay_out_result(mesh, o, outer, radius, run);
    measure();
  }
  if (run.result.converged) run.layout_failure = detail::layout_failure(run);
  if (run.result.converged && run.layout_failure.empty()) {
    run.layout_failure = detail::atlas_failure(run);
  }
}

// The flow (the disk preset: by one solve when one_solve, else or where that does not converge by
// the fixed point of repeated flows; the double where the surface's own triangulation stalls at
// the boundary or its class is not the double's) and the layout of its result.
// Returns true when the result is the disk preset's one solve.
bool flow_and_lay_out(const CompactMesh& mesh, const UniformizationOptions& o, int outer,
                      const TargetCurvature& target, bool one_solve, Uniformization& run) {
  bool by_one_solve = false;
  {
    // Its factorizations are freed before the layout, which needs none, and before the flow on the
    // double but where the disk's one solve stalled at the boundary's triangles (the surface's
    // repeated flows may follow that one).
    // The atlas's flat cone metric in the canonical class from the start (the input flipped
    // isometrically to its intrinsic Delaunay triangulation first, as CEPS does), not only once
    // the flow needs flips: on faces that are not Delaunay the input class's map is farther from
    // conformal (eight.off at 14 cones: QC p95 1.427 there, 1.225 in the canonical class).
    FlowOptions flow = o.flow;
    if (run.preset == TargetPreset::Atlas && flow.edge_flips == EdgeFlips::WhenNeeded) {
      flow.edge_flips = EdgeFlips::Always;
    }
    // The linear cone model's u is Newton's first step from u = 0.
    flow.start_is_a_step = run.preset == TargetPreset::Atlas;
    RicciFlowSolver solver(mesh, run.structure, flow, o.vertex_order);
    if (run.preset == TargetPreset::UnitDisk) {
      detail::OnDouble on_double;
      on_double.follows = detail::double_follows_boundary_stall(mesh, o, target, run);
      on_double.flow = [&] {
        if (!detail::may_flow_on_double(mesh, o, target, run)) return false;
        const FlowTotals before = run.totals;
        run.double_failure = detail::flow_on_double(mesh, o, outer, target, run);
        if (run.double_failure.empty()) return true;
        // The double's cost counts, not its flips or convergence floor: its result is not
        // delivered (as back_to_half below).
        run.totals.edge_flips = before.edge_flips;
        run.totals.flips_from_iteration = before.flips_from_iteration;
        run.totals.without_flips = before.without_flips;
        run.totals.attainable_residual = before.attainable_residual;
        return false;
      };
      by_one_solve =
          detail::reach_circle_domain(solver, mesh, outer, target, o, one_solve, on_double, run);
    } else {
      const std::optional<Eigen::VectorXd> start =
          run.preset == TargetPreset::Atlas
              ? std::optional<Eigen::VectorXd>(run.atlas.placement.u)
              : flow_start(mesh, run.structure, target, o.flow, o.vertex_order);
      run.result = solver.solve(target, start ? &*start : nullptr);
      run.totals.add(run.result);
    }
  }
  // On a surface with boundary the canonical class is its double's: flowed there where the
  // half's converged flow is in another (lightcycle-high.obj's 62-face part, free boundary:
  // quasi-conformal ratio p95 14.6 in the input triangulation's class, 5.06 on the double, CEPS
  // 5.12). The half's own result is delivered where the double's flow or layout fails.
  std::optional<Uniformization> half_run;
  // The half's own run back, with the double's cost (not its flips or convergence floor: its
  // result is not delivered) and why it was not.
  const auto back_to_half = [&](const std::string& why_not) {
    FlowTotals totals = run.totals;
    totals.edge_flips = half_run->totals.edge_flips;
    totals.flips_from_iteration = half_run->totals.flips_from_iteration;
    totals.without_flips = half_run->totals.without_flips;
    totals.attainable_residual = half_run->totals.attainable_residual;
    run = std::move(*half_run);
    run.totals = totals;
    run.double_failure = why_not;
    half_run.reset();
  };
  if (detail::may_flow_on_double(mesh, o, target, run)) {
    const std::string why_not = detail::flow_on_double(mesh, o, outer, target, run);
    if (!why_not.empty()) run.result.failure += "; " + why_not;
    lay_out_flow(mesh, o, outer, run);
  } else if (std::string why = detail::class_other_than_doubles(mesh, o, run); !why.empty()) {
    half_run = run;
    run.result.failure = std::move(why);  // kept as the run's doubled_because
    try {
      const std::string why_not = detail::flow_on_double(mesh, o, outer, target, run);
      if (run.doubled) lay_out_flow(mesh, o, outer, run);
      if (!run.doubled) {
        back_to_half(why_not);
      } else if (!run.layout_failure.empty()) {
        back_to_half(run.layout_failure);
      }
    } catch (const std::exception& e) {  // the half's converged flow stands
      back_to_half(failure_message(e));
    }
    if (!run.doubled) lay_out_flow(mesh, o, outer, run);
  } else {
    lay_out_flow(mesh, o, outer, run);
  }
  return by_one_solve;
}

// The delivered faces' D is held to the bound, and on a fine mesh it is the linear model's within
// a fraction of a percent, either way (glmark2-bunny: 0.20003 for the model's 0.19997, which cost
// a second run): the cones are placed for the bound less this margin.
constexpr double kPlacementMargin = 0.98;

}  // namespace

Uniformization detail::uniformize_once(const CompactMesh& mesh,
                                       const UniformizationOptions& request,
                                       const ConePlacement* unfolding) {
  const UniformizationOptions o = with_cone_values(mesh, request);
  Uniformization run;
  std::tie(run.preset, run.geometry) = resolve_request(mesh, o);
  run.scheme = o.scheme.scheme;
  run.tolerance = o.flow.tolerance;
  const int outer =
      run.preset == TargetPreset::UnitDisk ? outer_boundary_loop(mesh, mesh.input_lengths()) : -1;
  if (run.preset == TargetPreset::Atlas) {
    if (unfolding) {
      run.atlas.placement = *unfolding;
      run.atlas.bound = o.cone_placement.distortion_bound;
      run.atlas.unfolded = AtlasResult::Unfolded::NoAtlas;  // the caller says why, if otherwise
    } else if (o.cones.empty()) {
      // Each cone's curvature is below 2 pi: a closed surface of chi > 0 takes at least chi + 1
      // of them (a flow with fewer stalls after seconds: CGAL's camel at 2 cones, 3.8 s).
      const int chi = mesh.euler_characteristic();
      if (mesh.is_closed() && chi > 0 && cone_budget(o.cone_placement) < chi + 1) {
        throw InvalidTargetError(
            "atlas: a closed surface of genus 0 takes at least " + std::to_string(chi + 1) +
            " cones (each of curvature below 2 pi, theirs summing to " + std::to_string(2 * chi) +
            " pi); the cone budget is " + std::to_string(cone_budget(o.cone_placement)));
      }
      ConePlacementOptions placing = o.cone_placement;
      placing.distortion_bound *= kPlacementMargin;
      run.atlas.placement = place_cones(mesh, placing);
      run.atlas.bound = o.cone_placement.distortion_bound;
    } else {  // the user's cones, with their angles: no bound to reach, no linear model
      cone_target(mesh, o.cones);  // checks the vertices and angles
      for (const Cone& c : o.cones) {
        if (mesh.is_boundary_vertex(c.vertex)) {
          throw InvalidTargetError("atlas: cone at vertex " + std::to_string(c.vertex) +
                                   " on the boundary; the atlas's cones are interior vertices "
                                   "(its boundary is free)");
        }
      }
      ConePlacement& p = run.atlas.placement;
      p.cones = o.cones;
      p.u = Eigen::VectorXd::Zero(mesh.num_vertices());
      p.distortion = p.distortion_without_cones = p.max_deviation = std::nan("");
      p.bound_reached = true;
      run.atlas.user_cones = true;
      run.atlas.bound = std::nan("");
    }
  }
  const TargetCurvature target = initial_target(mesh, run.preset, o, outer, run.atlas.placement);
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

FlowTotals detail::cost_of(const FlowTotals& attempt) {
  FlowTotals cost = attempt;
  cost.edge_flips = 0;
  cost.flips_from_iteration = -1;
  cost.without_flips.clear();
  cost.attainable_residual = 0;
  return cost;
}

void detail::add_placement_cost(ConePlacement& to, const ConePlacement& from) {
  to.factorizations += from.factorizations;
  to.back_solves += from.back_solves;
  to.seconds += from.seconds;
}

void detail::add_cost(FlowTotals& totals, ConePlacement& placement, const Uniformization& attempt) {
  totals.add(cost_of(attempt.totals));
  add_placement_cost(placement, attempt.atlas.placement);
}

Uniformization detail::delivered_instead(const Uniformization& attempt, Uniformization instead) {
  FlowTotals totals = cost_of(attempt.totals);
  totals.add(instead.totals);
  instead.totals = totals;
  return instead;
}

std::string detail::why_not_valid(const Uniformization& run) {
  return run.converged() ? "gave no map: " + run.layout_failure
                         : "was not reached: " + run.result.failure;
}

namespace {

using detail::atlas_or_unfolded;
using detail::cost_of;
using detail::delivered_instead;
using detail::uniformize_as_requested;
using detail::why_not_valid;

// A request the automatic target answers as best it can: no cones, centre or axis.
bool best_effort(const UniformizationOptions& request) {
  return request.preset == TargetPreset::Automatic && request.cones.empty() &&
         request.center_vertex < 0 && request.axis_vertex < 0;
}

// The requested preset, and for the automatic target where the circle domain fails, the free
// boundary; where that fails too, `free_failure` says why.
Uniformization uniformize_by_target(const CompactMesh& mesh, const UniformizationOptions& request,
                                    std::string& free_failure) {
  Uniformization run = atlas_or_unfolded(mesh, request);
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

// The request's run, and the tangential scheme's where the Yamabe flow gives no map.
Uniformization unpacked(const CompactMesh& mesh, const UniformizationOptions& request) {
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

}  // namespace

Uniformization detail::uniformize_unpacked(const CompactMesh& mesh,
                                           const UniformizationOptions& request) {
  const auto start = detail::Clock::now();
  Uniformization run = unpacked(mesh, request);
  run.seconds = detail::seconds_since(start);
  return run;
}

Uniformization uniformize(const CompactMesh& mesh, const UniformizationOptions& request) {
  const auto start = detail::Clock::now();
  Uniformization run = detail::uniformize_unpacked(mesh, request);
  detail::pack_atlas(request.packing, run);
  run.seconds = detail::seconds_since(start);
  return run;
}

}  // namespace ricci
