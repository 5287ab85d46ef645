// The atlas's attempts after its first (pipeline/attempts.h).
#include "pipeline/attempts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "pipeline/texture_atlas.h"

namespace ricci::detail {

namespace {

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
// The attempt with loops (below) gives up where its common subdivision has more than this many
// faces per input face: CGAL's cheese at 8 cones has 23 (407k pieces, 18 s), the parts of
// gymnasium's forearm assembly at most 22.5; Cura's ZAV Max Pro at 8 cones, of 25 turns each, 235
// (3.9M pieces: the run gives up after 27 s, where its layout took 390 s to find 63 turned).
constexpr int kLoopedPiecesPerFace = 64;

// The cones' curvatures of least D (ConePlacement::least_distortion: at a budget that stops the
// placement above its bound) make u free at the cones, whose log-like peaks a coarse mesh draws
// on few faces: where the atlas's QC p95 on its faces is above this, the same cones with u held
// at 0 there are flowed too, and delivered where their QC p95 is at most kHeldQcGain times it.
// At BFF's 8 cones: CGAL's cross.off QC p95 3.95 with the curvatures of least D against 2.28
// (D 0.256 against 0.387), oblong.off 4.52 against 3.25, netgen's part1 2.77 against 2.16; below
// this, QC p95 rose by at most 0.13 on the real set and CGAL's but on geomview's mushroom (1.75 to
// 2.04, D 0.256 to 0.175), while D fell by a median of 16 % where it moved (docs/atlas.md). Not
// from 2, the bound of the unfolding's retries: a 32k-face part of gymnasium's Adroit shoulder
// (2.08 against 2.03) took a second placement, flow and layout for no atlas delivered, 11.9 s
// to 18.9.
constexpr double kHeldCurvaturesQc = 2.5;
constexpr double kHeldQcGain = 0.9;

// Whether flips that make loops (FlowOptions::loops) would change a flow made without them: it
// stalled for want of one, or converged on a triangulation where the Delaunay flips refused one,
// whose triangles there are no Delaunay triangulation's and can be slivers (gymnasium's Adroit
// shoulder at 8 cones converged so with 6 refused from the linear model's whole step, and its
// layout turned 2 faces over; from half of it, FlowOptions::start_is_a_step, its layout turns
// none).
bool wanted_loops(const FlowResult& flow) {
  return flow.stalled_for_loops || (flow.converged && flow.loops_refused > 0);
}

// The cones of an attempt, as the explanations name them: "D <= 0.2 (34 cones)".
std::string cones_for(const Uniformization& run) {
  std::ostringstream s;
  s.precision(3);
  const size_t n = run.atlas.placement.cones.size();
  s << "D <= " << run.atlas.bound << " (" << n << (n == 1 ? " cone)" : " cones)");
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

// Whether the unfolding's seams inside a chart join their sides by quarter turns, as
// --cone-angles quarter asks: each cone's angle a multiple of pi/2 to `tolerance`, the flow's (a
// box's corners, 3 pi/2 each; one turned off its axes and written to 7 digits misses them by up
// to 1e-6, and gets the placed cones rounded to quarter turns, to which the flow brings it), on a
// sphere or a disk, where every loop winds around cones only (on a torus or an annulus a loop
// around a handle or a hole turns as the surface makes it). The packing turns each chart as a
// whole.
bool by_quarter_turns(const CompactMesh& mesh, const ConePlacement& unfolding, double tolerance) {
  if (mesh.genus() != 0 || mesh.num_boundary_loops() > 1) return false;
  return std::all_of(unfolding.cones.begin(), unfolding.cones.end(), [&](const Cone& c) {
    const double quarter = kPi / 2;
    return std::abs(c.angle - quarter * std::round(c.angle / quarter)) <= tolerance;
  });
}

// The surface unfolded (unfolding_cones): its own metric, reached with no flow step, so it cannot
// stall. Not where it would break the request: more cones than `most` or the budget, or quarter
// turns asked for where it would not keep to them (by_quarter_turns); else why not. Its cones may
// be sharper than the placement's floor (min_cone_angle, which keeps a placed cone's wedge
// drawable): an unfolded cone's wedge is the input's own faces.
std::variant<Uniformization, std::string> unfolded_run(const CompactMesh& mesh,
                                                       const UniformizationOptions& request,
                                                       int most) {
  const ConePlacement unfolding = detail::unfolding_cones(mesh, request.flow.tolerance / 2);
  if (request.cone_placement.quarter_angles &&
      !by_quarter_turns(mesh, unfolding, request.flow.tolerance)) {
    return std::string("unfolding it would keep its own angles, not quarter turns");
  }
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
Uniformization atlas_within_bounds(const CompactMesh& mesh, const UniformizationOptions& asked,
                                   bool may_unfold = true) {
  UniformizationOptions request = asked;
  Uniformization run = uniformize_once(mesh, request);
  if (run.preset != TargetPreset::Atlas || run.atlas.user_cones) return run;
  // The curvatures of least D move u at the cones, and on a coarse surface the linear model is
  // far from the flow: where the flow then gives no atlas, the same cones with u held at 0 there
  // (CGAL's 90-vertex torus mpi_triang.off at 8 cones: the flow stalls with the former and
  // converges with the latter), and the attempts below from those; where it gives one far from
  // conformal (kHeldCurvaturesQc), the more conformal of the two.
  std::string least_failed;  // where the curvatures of least D gave no atlas, nor u = 0 did
  const bool failed_first = !run.valid() && run.result.stop != FlowStop::Cancelled;
  if (run.atlas.placement.least_distortion &&
      (failed_first || (run.valid() && run.quality.quasi_conformal_p95 > kHeldCurvaturesQc))) {
    request.cone_placement.least_distortion_angles = false;
    Uniformization held = uniformize_once(mesh, request);
    if (held.result.stop == FlowStop::Cancelled) return held;
    const bool delivered =
        held.valid() && (failed_first || held.quality.quasi_conformal_p95 <=
                                             kHeldQcGain * run.quality.quasi_conformal_p95);
    if (!failed_first && !delivered) {
      add_cost(run.totals, run.atlas.placement, held);
      return run;
    }
    held = delivered_instead(run, std::move(held));
    add_placement_cost(held.atlas.placement, run.atlas.placement);
    std::ostringstream gave;
    gave.precision(3);
    gave << "with the cones' curvatures of least D ";
    if (failed_first) {
      gave << "the atlas " << why_not_valid(run);
    } else {
      gave << "QC p95 on the faces was " << run.quality.quasi_conformal_p95;
    }
    if (delivered) {
      held.atlas.bound_instead = gave.str();
      held.atlas.held_curvatures = true;
      return held;
    }
    least_failed = gave.str();
    run = std::move(held);
  }
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
    if (!least_failed.empty()) why += "; " + least_failed;
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
  std::optional<Uniformization> unfolded;  // made, and no atlas
  auto unfolding = may_unfold ? unfolded_run(mesh, request, std::numeric_limits<int>::max())
                              : std::variant<Uniformization, std::string>(std::string());
  if (auto* u = std::get_if<Uniformization>(&unfolding)) {
    if (u->valid() || u->result.stop == FlowStop::Cancelled) {
      instead_of_failed(*u);
      return std::move(*u);
    }
    unfolded_failure = "; unfolded (" + std::to_string(u->atlas.placement.cones.size()) +
                       " cones): the atlas " + why_not_valid(*u);
    unfolded = std::move(*u);
  } else if (!std::get<std::string>(unfolding).empty()) {
    unfolded_failure = "; " + std::get<std::string>(unfolding);
  }
  // Nor that: where the first attempt's flow wanted an edge from a vertex to itself, its cones
  // once more with flips that make such loops (FlowOptions::loops). Last, for where they flow
  // instead of tighter cones that stalled they leave the faces farther from conformal
  // (docs/design.md): at BFF's budget of 8 cones 39 of the 169 parts of gymnasium's Adroit
  // forearm plate assembly stalled so, with no tighter bound to try and an unfolding of some 300
  // cones.
  std::optional<Uniformization> looped;  // made, and no atlas
  if (may_unfold && !request.flow.loops && wanted_loops(run.result)) {
    UniformizationOptions with_loops = request;
    with_loops.flow.loops = true;
    with_loops.max_pieces_per_face = kLoopedPiecesPerFace;
    Uniformization again = uniformize_once(mesh, with_loops);
    again.atlas.loops = true;
    if (again.valid() || again.result.stop == FlowStop::Cancelled) {
      instead_of_failed(again);
      if (unfolded) add_cost_to(again, *unfolded);
      again.atlas.bound_instead += unfolded_failure;
      return again;
    }
    looped = std::move(again);
  }
  // The first run's failure, and every attempt after it.
  std::string tried = least_failed.empty() ? "" : "; " + least_failed;
  for (const Uniformization& f : failed) {
    add_cost_to(run, f);
    tried += "; with the cones placed again for " + attempt(f);
  }
  if (unfolded) add_cost_to(run, *unfolded);
  tried += unfolded_failure;
  if (looped) {
    add_cost_to(run, *looped);
    tried += "; with its cones and flips that make edges from a vertex to itself: the atlas " +
             why_not_valid(*looped);
  }
  (run.converged() ? run.layout_failure : run.result.failure) += tried;
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

// `best`, the run for the request (atlas_within_bounds), with the cones placed again where the
// delivered faces' D exceeds the bound (kRetryMargin, kDistortionRetries).
Uniformization with_distortion_retries(const CompactMesh& mesh,
                                       const UniformizationOptions& request, Uniformization best) {
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

}  // namespace

Uniformization uniformize_as_requested(const CompactMesh& mesh,
                                       const UniformizationOptions& request) {
  return with_distortion_retries(mesh, request, atlas_within_bounds(mesh, request));
}

namespace {

// A coarse part's placed cones can leave its faces far from conformal (a 28-face oven window of
// gymnasium-robotics at 4 cones: QC p95 42 on its faces, BFF's 3.96 at 4 cones; a printer's bed
// plate of 396 faces at 4 cones, D 0.012: QC p95 5.78, BFF's 2.46 at 8). Where the delivered QC
// p95 is above this, the unfolding (QC 1 and D 0 on its faces) is delivered instead, its seams
// through more cones: through at most this many cones whatever its seams, through more (at most
// the budget; not at a budget the user gave) where its seams are within reach of the placed
// cones' (seams_within_reach). The genus-2 plates of gymnasium's Adroit forearm (about 317
// vertices, QC p95 3 to 11 at 10 to 64 cones) unfold so at once, QC 1, seams 7.8 to 10.5
// sqrt(area); before 2026-12-06 the cones of two tighter bounds were placed first, and most plates
// kept 146 to 204 cones, QC p95 1.07 to 1.70, seams 7.9 to 12. Where the unfolding is not
// delivered, the cones are placed again for a bound this many times below the last bound or D
// delivered, at most this many times, with at most this many times the first set's cones, and an
// attempt that lowers QC p95 enough (kQcGain) is delivered instead (the bed plate: 22 cones, QC
// p95 3.08, seams as long), and where that leaves QC p95 above this, the unfolding is weighed again
// against it (below).
constexpr double kUnfoldQc = 2;
constexpr int kUnfoldedCones = 64;
// Above this QC p95 (a square of texture drawn half as long again one way as the other) the
// unfolding, and where it does not serve the cones of tighter bounds, are delivered too where
// more conformal and their seams are at most kUnfoldSeams times the placed atlas's plus
// kUnfoldSeamsPlus sqrt(area): a box's six or seven placed cones shear its faces (CGAL's cube:
// QC p95 1.80, D 0.163), its eight corners unfold it (QC 1, D 0, seams 2.04 to 2.86 sqrt(area)),
// as BFF's eight cones do; a 74-face part of a game's garbage can, 4 cones, QC p95 1.63, seams
// 1.61, unfolds through its 36 vertices of curvature with seams of 4.54, not delivered, and gets
// the 29 cones of a tighter bound, QC p95 1.31, seams 3.64. The tighter bounds are tried here
// only where kQcRetryWork bounds the first set's cones (at least kVisibleQcCones) times the
// part's vertices: QC p95 between this and kUnfoldQc is a coarse part's (without this bound a
// 32k-face part of gymnasium's Adroit shoulder, 36 cones, was placed again at 144, 9 s more).
constexpr double kUnfoldVisibleQc = 1.5;
constexpr int kVisibleQcCones = 8;
constexpr double kUnfoldSeams = 2;
constexpr double kUnfoldSeamsPlus = 0.5;
constexpr double kQcTighter = 4;
constexpr int kQcRetries = 2;
constexpr int kQcCones = 4;
// An attempt is delivered instead where it leaves at most this share of the QC p95's excess over
// 1: more cones cost seams (PrusaSlicer's printbed-v2-300: seams 2.81 to 12.0 sqrt(area) for QC
// p95 7.89 to 7.81).
constexpr double kQcGain = 0.75;
// Not made where the first set has more than kUnfoldedCones cones and, times the part's vertices,
// more than kQcRetryWork (what a placement's back-solves and sweeps cost grows with both): a
// placement of hundreds of cones on a large part costs seconds to minutes (PrusaSlicer's aq bed,
// a part of 12.8k faces at 273 cones: placed again at 964, 225 s against 2.9 s, for QC p95 6.8 to
// 2.8; cura-zav-maxpro.stl's genus-97 plate at 255 cones, on 1.55M pieces: 86 s to 297 s for 10.1
// to 6.5), on a small one seconds at most (Cura's felixpro2 bed, 952 vertices at 68 cones: placed
// again at 128, QC p95 2.59 to 1.61, seams 11.8 to 8.9 sqrt(area), the run 0.5 s to 0.6 s, before
// 2026-12-06's unfolding at once, which now delivers it; a part of 1,446 vertices of gymnasium's
// Adroit forearm at 165 cones: at 660, 2.2 to 1.5, its run 1.4 s to 7.1 s).
// (Above kUnfoldQc, at most kUnfoldedCones cones they are made whatever the part's size, as
// before this rule: the placements of a few dozen cones cost little beside the part's flows.)
constexpr double kQcRetryWork = 64.0 * 4096;
bool nearer_conformal_affordable(const CompactMesh& mesh, const Uniformization& best,
                                 bool far_from_conformal) {
  const auto cones = static_cast<double>(best.atlas.placement.cones.size());
  if (!far_from_conformal) {
    return std::max<double>(cones, kVisibleQcCones) * mesh.num_vertices() <= kQcRetryWork;
  }
  return cones <= kUnfoldedCones || cones * mesh.num_vertices() <= kQcRetryWork;
}

// Whether seams of `length` are within kUnfoldSeams and kUnfoldSeamsPlus of the placed cones'.
bool seams_within_reach(double length, double placed) {
  return length <= kUnfoldSeams * placed + kUnfoldSeamsPlus;
}

// `best`'s cones placed again for tighter bounds (kQcTighter, kQcRetries, kQcCones), each valid
// attempt within the bound that lowers QC p95 enough (kQcGain) delivered instead, at the cost of
// all; where `best` is not far from conformal (QC p95 at most kUnfoldQc), only with seams within
// reach of its own.
Uniformization nearer_conformal_cones(const CompactMesh& mesh, const UniformizationOptions& request,
                                      Uniformization best, bool far_from_conformal) {
  const double first_seams = best.atlas.seam_length;
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
  // Far from conformal, each attempt first with as many cones as kQcRetryWork allows on the
  // part's vertices, then, where that gives no atlas nearer conformal enough, with at most `most`
  // (a low-poly boat of 80 vertices, all curved: 12 cones, QC p95 3.85; at 64 cones 7.01, at 73
  // 2.21; RatRig's vminion bed part, 4 cones, 4.67: at 64 cones 1.13, where more gave no atlas).
  const int wide =
      far_from_conformal
          ? std::min(cone_budget(request.cone_placement),
                     std::max(most, static_cast<int>(kQcRetryWork / mesh.num_vertices())))
          : most;
  // An attempt for a quarter of `bound` with at most `cap` cones. Its cones stopped at the cap
  // count as reached where the bound asked is met, as at a budget; a set that still has a cone
  // sharper than the floor is not delivered.
  const auto attempt = [&](int cap) {
    UniformizationOptions tighter = request;
    tighter.cone_placement.distortion_bound = bound / kQcTighter;
    tighter.cone_placement.max_cones = cap;
    // These cones are for a map nearer conformal, not a lower D: u = 0 at them, whose faces are
    // nearer their own shapes (with their curvatures of least D, the attempt for Dart's WAM
    // part, 68 cones, QC p95 1.47, no longer lowered it enough, and its 17 cones for 0.2, 1.63,
    // were delivered).
    tighter.cone_placement.least_distortion_angles = false;
    Uniformization run = atlas_within_bounds(mesh, tighter, false);
    if (run.result.stop != FlowStop::Cancelled) within_bound_asked(request, run.atlas.placement);
    return run;
  };
  const auto usable = [&](const Uniformization& run) {
    return run.valid() && run.atlas.placement.bound_reached && run.atlas.distortion <= allowed &&
           (far_from_conformal || seams_within_reach(run.atlas.seam_length, first_seams));
  };
  const auto nearer = [&](const Uniformization& run) {
    return usable(run) &&
           run.quality.quasi_conformal_p95 - 1 <= kQcGain * (best.quality.quasi_conformal_p95 - 1);
  };
  for (int k = 0; k < kQcRetries && best.quality.quasi_conformal_p95 >
                                        (far_from_conformal ? kUnfoldQc : kUnfoldVisibleQc);
       ++k) {
    Uniformization again = attempt(wide);
    if (again.result.stop != FlowStop::Cancelled && wide > most && !nearer(again)) {
      add_cost(spent, placed, again);
      again = attempt(most);
    }
    if (again.result.stop == FlowStop::Cancelled) {
      // Cancelled: every attempt's cost counts, before the cancelled one's own.
      add_cost(spent, placed, best);
      const FlowTotals own = again.totals;
      again.totals = spent;
      again.totals.add(own);
      add_placement_cost(again.atlas.placement, placed);
      return again;
    }
    if (nearer(again)) {
      why += (why.empty() ? "" : "; ") + qc_was(best);
      if (!best.atlas.bound_instead.empty()) why += "; " + best.atlas.bound_instead;
      add_cost(spent, placed, best);
      best = std::move(again);
    } else {
      add_cost(spent, placed, again);
      if (!usable(again)) break;
    }
    bound = std::min(bound / kQcTighter, best.atlas.distortion);
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

}  // namespace

namespace {

Uniformization atlas_or_unfolded_run(const CompactMesh& mesh,
                                     const UniformizationOptions& request) {
  // A run the unfolding may replace: an atlas of placed cones (not one that flowed with loops,
  // delivered where the unfolding gave none).
  const auto placed_atlas = [](const Uniformization& run) {
    return run.preset == TargetPreset::Atlas && run.valid() && !run.atlas.user_cones &&
           run.atlas.unfolded == AtlasResult::Unfolded::No && !run.atlas.loops;
  };
  // The unfolding `unfolded` in place of `replaced`, at the cost of both, and why.
  const auto unfolded_instead = [&](const Uniformization& replaced, Uniformization& unfolded,
                                    AtlasResult::Unfolded kind) {
    std::string why =
        kind == AtlasResult::Unfolded::WithinBound ? d_was(replaced) : qc_was(replaced);
    if (!replaced.atlas.bound_instead.empty()) why += "; " + replaced.atlas.bound_instead;
    Uniformization run = delivered_instead(replaced, std::move(unfolded));
    add_placement_cost(run.atlas.placement, replaced.atlas.placement);
    run.atlas.unfolded = kind;
    run.atlas.bound_instead = why;
    run.atlas.bound_asked = request.cone_placement.distortion_bound;
    return run;
  };
  // A cancelled unfolding, at the cost of `replaced` and the attempts before it.
  const auto cancelled_instead = [&](const Uniformization& replaced, Uniformization& cancelled) {
    Uniformization run = delivered_instead(replaced, std::move(cancelled));
    add_placement_cost(run.atlas.placement, replaced.atlas.placement);
    return run;
  };
  const auto wide = [](const Uniformization& unfolded) {
    return static_cast<int>(unfolded.atlas.placement.cones.size()) > kUnfoldedCones;
  };
  // Whether `unfolded` may replace `than` for QC: valid, more conformal, and with seams within
  // reach of `than`'s unless it unfolds through at most kUnfoldedCones cones and `than` is far
  // from conformal (`far`).
  const auto more_conformal = [&](const Uniformization& unfolded, const Uniformization& than,
                                  bool far) {
    return unfolded.valid() &&
           unfolded.quality.quasi_conformal_p95 < than.quality.quasi_conformal_p95 &&
           ((far && !wide(unfolded)) ||
            seams_within_reach(unfolded.atlas.seam_length, than.atlas.seam_length));
  };

  // Through more than kUnfoldedCones cones an unfolding is made only where the budget is not the
  // user's (who asked for at most that many cones, and that none be placed again for QC).
  const int widest =
      request.cone_placement.max_cones != 0 ? kUnfoldedCones : std::numeric_limits<int>::max();
  Uniformization best = atlas_within_bounds(mesh, request);
  // Where the first atlas that flowed (after the tighter bounds its stalls took) is far from
  // conformal, the unfolding through as many cones as allowed, before its cones are placed again
  // for the bound or for QC; through more than kUnfoldedCones delivered only where its seams are
  // within reach of that atlas's.
  std::optional<Uniformization> unfolding;
  int tried_with = 0;  // the most cones an unfolding was asked to take (0: none asked)
  if (placed_atlas(best) && best.quality.quasi_conformal_p95 > kUnfoldQc) {
    auto made = unfolded_run(mesh, request, widest);
    tried_with = widest;
    if (auto* u = std::get_if<Uniformization>(&made)) {
      if (u->result.stop == FlowStop::Cancelled) return cancelled_instead(best, *u);
      if (more_conformal(*u, best, true)) {
        return unfolded_instead(best, *u, AtlasResult::Unfolded::MoreConformal);
      }
      unfolding = std::move(*u);
    }
  }
  best = with_distortion_retries(mesh, request, std::move(best));
  // An unfolding made but not delivered: its cost counted once, in the run delivered.
  const auto with_unfolding_cost = [&](Uniformization run) {
    if (unfolding) add_cost(run.totals, run.atlas.placement, *unfolding);
    return run;
  };
  // Where the delivered faces' D breaks the bound that the cones' linear model met (the summary's
  // warning), the unfolding meets it (D 0) with as many cones as the budget allows, whatever its
  // seams: a CAD part of 100 holes, 258 interior vertices all curved, whose cones for 0.2 left
  // 0.218 on its faces (QC p95 23) and those of tighter bounds stalled.
  const bool above_bound = best.atlas.placement.bound_reached &&
                           best.atlas.distortion > request.cone_placement.distortion_bound;
  const bool far_from_conformal = best.quality.quasi_conformal_p95 > kUnfoldQc;
  if (!placed_atlas(best) ||
      !(far_from_conformal || best.quality.quasi_conformal_p95 > kUnfoldVisibleQc || above_bound)) {
    return with_unfolding_cost(std::move(best));
  }
  // The atlas the retries for D deliver is weighed as the first one was: above the bound against
  // the unfolding through as many cones as the budget allows; far from conformal through as many
  // as allowed above; else through at most kUnfoldedCones. Made here where not made above with as
  // many.
  const int most = above_bound          ? std::numeric_limits<int>::max()
                   : far_from_conformal ? widest
                                        : kUnfoldedCones;
  if (!unfolding && most > tried_with) {
    auto made = unfolded_run(mesh, request, most);
    if (auto* u = std::get_if<Uniformization>(&made)) {
      if (u->result.stop == FlowStop::Cancelled) return cancelled_instead(best, *u);
      unfolding = std::move(*u);
    }
  }
  // One made above through more cones than may be taken here is not delivered here.
  const bool may_deliver = unfolding && (most > kUnfoldedCones || !wide(*unfolding));
  if (may_deliver &&
      (above_bound ? unfolding->valid() : more_conformal(*unfolding, best, far_from_conformal))) {
    return unfolded_instead(
        best, *unfolding,
        above_bound ? AtlasResult::Unfolded::WithinBound : AtlasResult::Unfolded::MoreConformal);
  }
  // Cones for tighter bounds only where QC p95 is above kUnfoldVisibleQc; not where the user's
  // budget fixed the count of cones (BFF's 8, say), nor where they cost too much.
  if (!(best.quality.quasi_conformal_p95 > kUnfoldVisibleQc) ||
      request.cone_placement.max_cones != 0 ||
      !nearer_conformal_affordable(mesh, best, far_from_conformal)) {
    return with_unfolding_cost(std::move(best));
  }
  best = nearer_conformal_cones(mesh, request, std::move(best), far_from_conformal);
  // Still far from conformal with them, the unfolding through more than kUnfoldedCones cones
  // where its seams are within reach of theirs (a desk of Sweet Home 3D's furniture, 672 faces,
  // genus 1: 90 cones, QC p95 5.2 on its pieces, seams 18.3 sqrt(area); unfolded through its 175
  // vertices of curvature, QC 1, seams 15.6).
  if (!unfolding || !wide(*unfolding) || best.result.stop == FlowStop::Cancelled || !best.valid() ||
      !(best.quality.quasi_conformal_p95 > kUnfoldQc)) {
    return with_unfolding_cost(std::move(best));
  }
  if (more_conformal(*unfolding, best, true)) {
    return unfolded_instead(best, *unfolding, AtlasResult::Unfolded::MoreConformal);
  }
  return with_unfolding_cost(std::move(best));
}

}  // namespace

Uniformization atlas_or_unfolded(const CompactMesh& mesh, const UniformizationOptions& request) {
  Uniformization run = atlas_or_unfolded_run(mesh, request);
  // The placement's margin (or a tighter attempt's bound) can leave the linear model's D above
  // the bound it was placed for yet within the one asked: reached, then (hand.off at 8 cones, D
  // 0.198 for a placement bound of 0.196, had warned that 0.2 was not reached).
  if (run.preset == TargetPreset::Atlas && !run.atlas.user_cones) {
    within_bound_asked(request, run.atlas.placement);
    // And where the delivered faces' D is within it, whatever the model's (the cow at 64 cones
    // for 0.1: 0.0987 on its faces, the model's 0.114, had warned of a bound not reached).
    ConePlacement& p = run.atlas.placement;
    if (!p.bound_reached && !p.sharp_cone && !p.cones.empty() && run.valid() &&
        run.atlas.distortion <= request.cone_placement.distortion_bound) {
      p.bound_reached = true;
      p.why_not.clear();
    }
  }
  return run;
}

}  // namespace ricci::detail
