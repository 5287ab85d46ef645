#include "ricci/pipeline/uniformize.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <optional>
#include <sstream>
#include <variant>
#include <vector>

#include "flow/spherical_start.h"
#include "pipeline/circle_domain.h"
#include "pipeline/delivered_layout.h"
#include "pipeline/disk_drawing.h"
#include "pipeline/doubled_surface.h"
#include "pipeline/texture_atlas.h"
#include "ricci/flow/ricci_flow.h"
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
  if (o.cones.empty() || o.preset == TargetPreset::Atlas) return o;
  o.preset = TargetPreset::Values;
  o.values = cone_target(mesh, o.cones).values();
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
    geometry = o.geometry.value_or(
        geometry_for_target(mesh, TargetCurvature::from_values(mesh, o.values)));
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
    // Its factorizations are freed before the flow on the double and the layout, which need none.
    // The atlas's flat cone metric in the canonical class from the start (the input flipped
    // isometrically to its intrinsic Delaunay triangulation first, as CEPS does), not only once
    // the flow needs flips: on faces that are not Delaunay the input class's map is farther from
    // conformal (eight.off at 14 cones: QC p95 1.427 there, 1.225 in the canonical class).
    FlowOptions flow = o.flow;
    if (run.preset == TargetPreset::Atlas && flow.edge_flips == EdgeFlips::WhenNeeded) {
      flow.edge_flips = EdgeFlips::Always;
    }
    RicciFlowSolver solver(mesh, run.structure, flow, o.vertex_order);
    if (run.preset == TargetPreset::UnitDisk) {
      by_one_solve = detail::reach_circle_domain(solver, mesh, outer, target, o, one_solve, run);
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
      back_to_half(e.what());
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

// The run for the preset resolved from the request (the atlas's cones placed once, or `unfolding`,
// unfolding_cones, where given).
Uniformization uniformize_once(const CompactMesh& mesh, const UniformizationOptions& request,
                               const ConePlacement* unfolding = nullptr) {
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

// A cone placement's cost added to another's.
void add_placement_cost(ConePlacement& to, const ConePlacement& from) {
  to.factorizations += from.factorizations;
  to.back_solves += from.back_solves;
  to.seconds += from.seconds;
}

// What an attempt not delivered cost, its flows and its cone placement, added to these.
void add_cost(FlowTotals& totals, ConePlacement& placement, const Uniformization& attempt) {
  totals.add(cost_of(attempt.totals));
  add_placement_cost(placement, attempt.atlas.placement);
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

// Tighter distortion bounds place more cones, closer together, whose flat metric is nearer the
// input's. Where the flow with the cones for the bound asked is not reached (on CAD parts of high
// genus the Delaunay triangulation of their metric can need an edge from a vertex to itself,
// which the flips refuse, and the flow stalls: cura-felixpro2.obj, openscad-tardis.stl) or their
// layout fails, the cones for half the bound, at most this many times. Not where the placement
// stopped short of its bound (at the cone budget): a tighter one places no other cones.
constexpr int kTighterBounds = 2;
// Where those stall too and the placement used more cones than this under the default budget,
// the cones are placed once more within this budget, each relocated among several peaks (the
// sweeps' way at a budget): cura-zav-maxpro.stl (genus 97) stalls with the 262 cones for 0.2,
// the 461 for 0.1 and the 739 for 0.05, and flows with the 255 that a budget of 256 leaves for
// 0.2 (D 0.158 on its faces).
constexpr int kFewerCones = 256;

// The cones of an attempt, as the explanations name them: "D <= 0.2 (34 cones)".
std::string cones_for(const Uniformization& run) {
  std::ostringstream s;
  s.precision(3);
  s << "D <= " << run.atlas.bound << " (" << run.atlas.placement.cones.size() << " cones)";
  return s.str();
}

// One attempt, as the explanations list it: "D <= 0.2 (34 cones): the atlas was not reached: ...".
std::string attempt(const Uniformization& run) {
  return cones_for(run) + ": the atlas " + why_not_valid(run);
}

// The budget can stop a tighter placement short of its bound, within the one asked: reached then.
void within_bound_asked(const UniformizationOptions& request, ConePlacement& p) {
  // (No cones where the placement found no flat metric: its D, of u = 0, is no atlas's.)
  if (!p.bound_reached && !p.sharp_cone && !p.cones.empty() &&
      p.distortion <= request.cone_placement.distortion_bound) {
    p.bound_reached = true;
    p.why_not.clear();
  }
}

// The surface unfolded (unfolding_cones): its own metric, reached with no flow step, so it cannot
// stall. Not where it would break the request: more cones than `most` or the budget, or quarter
// turns asked for; else why not. Its cones may be sharper than the placement's floor
// (min_cone_angle, which keeps a placed cone's wedge drawable): an unfolded cone's wedge is the
// input's own faces.
std::variant<Uniformization, std::string> unfolded_run(const CompactMesh& mesh,
                                                       const UniformizationOptions& request,
                                                       int most) {
  if (request.cone_placement.quarter_angles) {
    return std::string("unfolding it would keep its own angles, not quarter turns");
  }
  const ConePlacement unfolding = detail::unfolding_cones(mesh, request.flow.tolerance / 2);
  const int budget = cone_budget(request.cone_placement);
  if (static_cast<int>(unfolding.cones.size()) > std::min(most, budget)) {
    return "unfolding it would take " + std::to_string(unfolding.cones.size()) + " cones, above " +
           (most < budget ? "the " + std::to_string(most) + " it may take"
                          : "the budget of " + std::to_string(budget));
  }
  UniformizationOptions own_metric = request;
  own_metric.flow.edge_flips = EdgeFlips::Never;  // u = 0: the input's triangulation is drawn
  return uniformize_once(mesh, own_metric, &unfolding);
}

// The run for the preset resolved from the request; the atlas's placed cones again for tighter
// bounds while the run gives no atlas, and where none does, the surface unfolded (unfolded_run)
// if `may_unfold`.
Uniformization atlas_within_bounds(const CompactMesh& mesh, const UniformizationOptions& request,
                                   bool may_unfold = true) {
  Uniformization run = uniformize_once(mesh, request);
  if (run.preset != TargetPreset::Atlas || run.atlas.user_cones) return run;
  std::vector<Uniformization> failed;  // the attempts after the first that gave no atlas
  std::optional<Uniformization> last;
  for (int k = 0; k < kTighterBounds; ++k) {
    const Uniformization& tried = last ? *last : run;
    if (tried.valid() || tried.result.stop == FlowStop::Cancelled ||
        !tried.atlas.placement.bound_reached) {
      break;
    }
    UniformizationOptions tighter = request;
    tighter.cone_placement.distortion_bound = tried.atlas.bound / 2;
    if (last) failed.push_back(std::move(*last));
    last = uniformize_once(mesh, tighter);
  }
  if (last && !last->valid() && last->result.stop != FlowStop::Cancelled &&
      request.cone_placement.max_cones == 0 &&
      static_cast<int>(run.atlas.placement.cones.size()) > kFewerCones) {
    UniformizationOptions fewer = request;
    fewer.cone_placement.max_cones = kFewerCones;
    failed.push_back(std::move(*last));
    last = uniformize_once(mesh, fewer);
  }
  if (!last && (run.valid() || run.result.stop == FlowStop::Cancelled)) return run;
  if (last && last->result.stop == FlowStop::Cancelled) return std::move(*last);
  const auto add_cost_to = [](Uniformization& to, const Uniformization& attempt) {
    add_cost(to.totals, to.atlas.placement, attempt);
  };
  // `delivered` in place of the first run and the attempts that failed, at their cost too.
  const auto instead_of_failed = [&](Uniformization& delivered) {
    const FlowTotals own = delivered.totals;
    delivered.totals = FlowTotals();
    add_cost_to(delivered, run);
    for (const Uniformization& f : failed) add_cost_to(delivered, f);
    delivered.totals.add(own);
    std::string why = "with the cones for " + attempt(run);
    for (const Uniformization& f : failed) why += "; with those for " + attempt(f);
    delivered.atlas.bound_instead = why;
  };
  if (last && last->valid()) {
    instead_of_failed(*last);
    within_bound_asked(request, last->atlas.placement);
    return std::move(*last);
  }
  if (last) failed.push_back(std::move(*last));
  // None gave an atlas: the surface unfolded, where that keeps to the request.
  std::string unfolded_failure;
  auto unfolding = may_unfold ? unfolded_run(mesh, request, std::numeric_limits<int>::max())
                              : std::variant<Uniformization, std::string>(std::string());
  if (auto* u = std::get_if<Uniformization>(&unfolding)) {
    if (u->valid() || u->result.stop == FlowStop::Cancelled) {
      instead_of_failed(*u);
      return std::move(*u);
    }
    unfolded_failure = "; unfolded (" + std::to_string(u->atlas.placement.cones.size()) +
                       " cones): the atlas " + why_not_valid(*u);
    failed.push_back(std::move(*u));
  } else if (!std::get<std::string>(unfolding).empty()) {
    unfolded_failure = "; " + std::get<std::string>(unfolding);
  }
  // The first run's failure, and every attempt after it.
  std::string tried;
  for (const Uniformization& f : failed) {
    add_cost_to(run, f);
    if (f.atlas.unfolded == AtlasResult::Unfolded::No) {
      tried += "; with the cones placed again for " + attempt(f);
    }
  }
  (run.converged() ? run.layout_failure : run.result.failure) += tried + unfolded_failure;
  return run;
}

// What a delivered run's figure was, as the explanations say it: "with the cones for D <= 0.2
// (7 cones) QC p95 on the faces was 3.1".
std::string cones_gave(const Uniformization& run, const std::string& figure, double value) {
  std::ostringstream why;
  why.precision(3);
  why << "with the cones for " << cones_for(run) << " " << figure << " was " << value;
  return why.str();
}
std::string d_was(const Uniformization& run) {
  return cones_gave(run, "the delivered faces' D", run.atlas.distortion);
}
std::string qc_was(const Uniformization& run) {
  return cones_gave(run, "QC p95 on the faces", run.quality.quasi_conformal_p95);
}

// The delivered faces' D can exceed the bound the cones' linear model met: the exact flat metric
// is not the linear model's, and the faces of a coarse part lag its vertices (sumo-tram.obj's small
// parts: up to 0.3 at 0.2). Then the cones are placed again for the bound their linear model met
// scaled down by that excess (and this margin), at most this many times, each from the last
// attempt's (more cones can raise D on a coarse part: oblong-shuffled.off 0.206 with 8, 0.267
// with 8 others, 0.157 with 12), and the atlas with the lowest D among the valid ones is
// delivered.
constexpr double kRetryMargin = 0.95;
constexpr int kDistortionRetries = 2;

Uniformization uniformize_as_requested(const CompactMesh& mesh,
                                       const UniformizationOptions& request) {
  Uniformization best = atlas_within_bounds(mesh, request);
  const double asked = request.cone_placement.distortion_bound;
  best.atlas.bound_asked = asked;
  const auto above = [&](const Uniformization& run) {
    return run.preset == TargetPreset::Atlas && !run.atlas.user_cones && run.valid() &&
           run.atlas.placement.bound_reached && run.atlas.distortion > asked;
  };
  // What the attempts not delivered cost, in the order they were spent, and what each gave.
  FlowTotals spent;
  ConePlacement placed;
  std::vector<std::string> gave;  // per attempt, the first run's first
  size_t chosen = 0;              // the attempt delivered
  const auto describe = [](const Uniformization& run) {
    return run.valid() ? d_was(run) : "with the cones for " + attempt(run);
  };
  gave.push_back(describe(best));
  // Each attempt's bound from the last attempt's, which need not be the best one.
  double bound = best.atlas.bound, linear = best.atlas.placement.distortion;
  double distortion = best.atlas.distortion;
  for (int k = 0; k < kDistortionRetries && above(best) && distortion > asked; ++k) {
    UniformizationOptions tighter = request;
    tighter.cone_placement.distortion_bound =
        kRetryMargin * std::min(bound, linear) * asked / distortion;
    // Not unfolded here: an atlas of placed cones was given, its D above the bound.
    Uniformization again = atlas_within_bounds(mesh, tighter, false);
    again.atlas.bound_asked = asked;
    if (again.result.stop == FlowStop::Cancelled) return again;
    gave.push_back(describe(again));
    const bool usable = again.valid() && again.atlas.placement.bound_reached;
    if (usable) {
      bound = again.atlas.bound, linear = again.atlas.placement.distortion;
      distortion = again.atlas.distortion;
    }
    if (usable && again.atlas.distortion < best.atlas.distortion) {
      add_cost(spent, placed, best);
      best = std::move(again);
      chosen = gave.size() - 1;
    } else {
      add_cost(spent, placed, again);
      if (!usable) break;
    }
  }
  if (gave.size() == 1) return best;
  const FlowTotals own = best.totals;
  best.totals = spent;
  best.totals.add(own);
  add_placement_cost(best.atlas.placement, placed);
  if (chosen > 0) {
    std::string why;
    for (size_t a = 0; a < gave.size(); ++a) {
      if (a != chosen) why += (why.empty() ? "" : "; ") + gave[a];
    }
    if (!best.atlas.bound_instead.empty()) why += "; " + best.atlas.bound_instead;
    best.atlas.bound_instead = why;
    within_bound_asked(request, best.atlas.placement);
  }
  return best;
}

// A coarse part's placed cones can leave its faces far from conformal (a 28-face oven window of
// gymnasium-robotics at 4 cones: QC p95 42 on its faces, BFF's 3.96 at 4 cones; a printer's bed
// plate of 396 faces at 4 cones, D 0.012: QC p95 5.78, BFF's 2.46 at 8). Where the delivered QC
// p95 is above this and the part unfolds with at most this many cones, the unfolding (QC 1 and D 0
// on its faces) is delivered instead, its seams through more cones. Where it does not, the cones
// are placed again for a bound this many times below the last bound or D delivered, at most this
// many times, with at most this many times the first set's cones, and an attempt that lowers QC
// p95 enough (kQcGain) is delivered instead (the bed plate: 22 cones, QC p95 3.08, seams as
// long).
constexpr double kUnfoldQc = 2;
constexpr int kUnfoldedCones = 64;
constexpr double kQcTighter = 4;
constexpr int kQcRetries = 2;
constexpr int kQcCones = 4;
// An attempt is delivered instead where it leaves at most this share of the QC p95's excess over
// 1: more cones cost seams (PrusaSlicer's printbed-v2-300: seams 2.81 to 12.0 sqrt(area) for QC
// p95 7.89 to 7.81).
constexpr double kQcGain = 0.75;
// Not made where the first set has more than kUnfoldedCones cones: a placement of hundreds of
// cones costs seconds to minutes (PrusaSlicer's aq bed, a part of 12.8k faces at 273 cones: placed
// again at 964, 225 s against 2.9 s, for QC p95 6.8 to 2.8; cura-zav-maxpro.stl's genus-97 plate
// at 255 cones, on 1.55M pieces: 86 s to 297 s for 10.1 to 6.5).

// `best`'s cones placed again for tighter bounds (kQcTighter, kQcRetries, kQcCones), each valid
// attempt within the bound that lowers QC p95 enough (kQcGain) delivered instead, at the cost of
// all.
Uniformization nearer_conformal_cones(const CompactMesh& mesh, const UniformizationOptions& request,
                                      Uniformization best) {
  FlowTotals spent;
  ConePlacement placed;
  std::string why;
  // No atlas whose D is above both the bound asked and the first one's.
  const double allowed = std::max(request.cone_placement.distortion_bound, best.atlas.distortion);
  // Each attempt's bound below the last one's and the best atlas's D; its cones at most
  // kQcCones times the first's (or as many as an unfolding may take).
  double bound = std::min(best.atlas.bound, best.atlas.distortion);
  const int most = std::min(
      cone_budget(request.cone_placement),
      std::max(kUnfoldedCones, kQcCones * static_cast<int>(best.atlas.placement.cones.size())));
  for (int k = 0; k < kQcRetries && best.quality.quasi_conformal_p95 > kUnfoldQc; ++k) {
    UniformizationOptions tighter = request;
    tighter.cone_placement.distortion_bound = bound / kQcTighter;
    tighter.cone_placement.max_cones = most;
    Uniformization again = atlas_within_bounds(mesh, tighter, false);
    if (again.result.stop == FlowStop::Cancelled) {
      // Cancelled: every attempt's cost counts, before the cancelled one's own.
      add_cost(spent, placed, best);
      const FlowTotals own = again.totals;
      again.totals = spent;
      again.totals.add(own);
      add_placement_cost(again.atlas.placement, placed);
      return again;
    }
    // Its cones stopped at `most` count as reached where the bound asked is met, as at a budget;
    // a set that still has a cone sharper than the floor is not delivered.
    within_bound_asked(request, again.atlas.placement);
    const bool usable =
        again.valid() && again.atlas.placement.bound_reached && again.atlas.distortion <= allowed;
    if (usable &&
        again.quality.quasi_conformal_p95 - 1 <= kQcGain * (best.quality.quasi_conformal_p95 - 1)) {
      why += (why.empty() ? "" : "; ") + qc_was(best);
      if (!best.atlas.bound_instead.empty()) why += "; " + best.atlas.bound_instead;
      add_cost(spent, placed, best);
      best = std::move(again);
    } else {
      add_cost(spent, placed, again);
      if (!usable) break;
    }
    bound = std::min(tighter.cone_placement.distortion_bound, best.atlas.distortion);
  }
  const FlowTotals own = best.totals;
  best.totals = spent;
  best.totals.add(own);
  add_placement_cost(best.atlas.placement, placed);
  if (!why.empty()) {
    if (!best.atlas.bound_instead.empty()) why += "; " + best.atlas.bound_instead;
    best.atlas.bound_instead = why;
    best.atlas.bound_asked = request.cone_placement.distortion_bound;
  }
  return best;
}

Uniformization atlas_or_unfolded(const CompactMesh& mesh, const UniformizationOptions& request) {
  Uniformization best = uniformize_as_requested(mesh, request);
  // Where the delivered faces' D breaks the bound that the cones' linear model met (the summary's
  // warning), the unfolding meets it (D 0) with as many cones as the budget allows, whatever its
  // seams: a CAD part of 100 holes, 258 interior vertices all curved, whose cones for 0.2 left
  // 0.218 on its faces (QC p95 23) and those of tighter bounds stalled.
  const bool above_bound = best.atlas.placement.bound_reached &&
                           best.atlas.distortion > request.cone_placement.distortion_bound;
  if (best.preset != TargetPreset::Atlas || !best.valid() || best.atlas.user_cones ||
      best.atlas.unfolded != AtlasResult::Unfolded::No ||
      !(best.quality.quasi_conformal_p95 > kUnfoldQc || above_bound)) {
    return best;
  }
  auto unfolding =
      unfolded_run(mesh, request, above_bound ? std::numeric_limits<int>::max() : kUnfoldedCones);
  auto* u = std::get_if<Uniformization>(&unfolding);
  if (u && u->result.stop == FlowStop::Cancelled) {
    *u = delivered_instead(best, std::move(*u));
    return std::move(*u);
  }
  const bool better =
      u && u->valid() &&
      (above_bound || u->quality.quasi_conformal_p95 < best.quality.quasi_conformal_p95);
  if (!better) {
    if (u) add_cost(best.totals, best.atlas.placement, *u);
    // Cones for tighter bounds only where QC p95 is above kUnfoldQc; not where the user's budget
    // fixed the count of cones (BFF's 8, say), nor from more than kUnfoldedCones.
    if (!(best.quality.quasi_conformal_p95 > kUnfoldQc) || request.cone_placement.max_cones != 0 ||
        static_cast<int>(best.atlas.placement.cones.size()) > kUnfoldedCones) {
      return best;
    }
    return nearer_conformal_cones(mesh, request, std::move(best));
  }
  std::string why = above_bound ? d_was(best) : qc_was(best);
  if (!best.atlas.bound_instead.empty()) why += "; " + best.atlas.bound_instead;
  *u = delivered_instead(best, std::move(*u));
  add_placement_cost(u->atlas.placement, best.atlas.placement);
  u->atlas.unfolded =
      above_bound ? AtlasResult::Unfolded::WithinBound : AtlasResult::Unfolded::MoreConformal;
  u->atlas.bound_instead = why;
  u->atlas.bound_asked = request.cone_placement.distortion_bound;
  return std::move(*u);
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

}  // namespace

Uniformization detail::uniformize_unpacked(const CompactMesh& mesh,
                                           const UniformizationOptions& request) {
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

Uniformization uniformize(const CompactMesh& mesh, const UniformizationOptions& request) {
  Uniformization run = detail::uniformize_unpacked(mesh, request);
  detail::pack_atlas(request.packing, run);
  return run;
}

}  // namespace ricci
