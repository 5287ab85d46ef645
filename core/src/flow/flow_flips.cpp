// The flow's triangulation: edge flips to (power) Delaunay, when they start, and the walk to a
// start.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

#include "flow/flow_state.h"
#include "flow/pattern_obstruction.h"
#include "ricci/mesh/errors.h"

namespace ricci {

using detail::Clock;
using detail::seconds_since;

void detail::FlowState::use_free_vertices(const TargetCurvature& target) {
  std::vector<int> index =
      detail::free_vertex_index(mesh.num_vertices(), structure.geometry, target);
  if (index != free_index) pattern_current = false;
  free_index = std::move(index);
  if (!pattern_current) steps.set_pattern(triangulation, free_index, flip_sequence.empty());
  pattern_current = true;
}

// Flips to (power) Delaunay; a changed connectivity needs a new Hessian pattern and analysis.
void detail::FlowState::keep_delaunay() {
  if (!flipping) return;
  const auto t = Clock::now();
  if (options.delaunay_class && canonical_class && !input_made_delaunay && flip_sequence.empty() &&
      structure.geometry != Geometry::Hyperbolic && is_yamabe(structure) && structure.u0.isZero()) {
    input_made_delaunay = true;
    const FlipReport isometric = make_input_delaunay(triangulation, structure);
    if (!isometric.sequence.empty()) {
      result.delaunay_class = true;
      result.num_flips += isometric.flips;
      flip_sequence = isometric.sequence;
      metric = evaluate_metric(triangulation, structure, u);
      ++result.connectivity_changes;
      steps.set_pattern(triangulation, free_index, false);
    }
  }
  const FlipReport flips =
      make_delaunay(triangulation, structure, u, metric, 10 * mesh.num_edges(), options.loops);
  result.num_flips += flips.flips;
  result.loops_refused = flips.loops_refused;
  flip_sequence.insert(flip_sequence.end(), flips.sequence.begin(), flips.sequence.end());
  // A flip that was undone leaves the same triangles in other face slots: the pattern's per-face
  // entries change too.
  if (!flips.sequence.empty()) {
    ++result.connectivity_changes;
    steps.set_pattern(triangulation, free_index, false);
  }
  times.flips += seconds_since(t);
}

// The triangulation a line search flipped to reach its accepted point.
void detail::FlowState::adopt_flips(detail::LineSearch& step) {
  triangulation = std::move(*step.flipped);
  structure.eta = std::move(step.flipped_eta);
  result.num_flips += step.flips.flips;
  flip_sequence.insert(flip_sequence.end(), step.flips.sequence.begin(), step.flips.sequence.end());
  ++result.connectivity_changes;
  steps.set_pattern(triangulation, free_index, false);
}

// EdgeFlips::WhenNeeded: flips from here on, starting from the current u.
void detail::FlowState::start_flipping(int iteration, const std::string& why) {
  flipping = true;
  result.flips_from_iteration = iteration;
  result.without_flips = why;
  stall = detail::StallWindow();
  lm_weight = 1;
  if (blocked_walk) {
    // Newton got stuck after a blocked walk: the walk again from its origin, with flips, as it
    // goes with flips always (it costs no factorization).
    u = blocked_walk->first;
    metric = evaluate_metric(triangulation, structure, u);
    keep_delaunay();
    const Eigen::VectorXd start = std::move(blocked_walk->second);
    blocked_walk.reset();
    walk_to(start);
  } else {
    if (iteration <= kStartOverByIteration) {
      u = newton_start;
      metric = evaluate_metric(triangulation, structure, u);
    }
    keep_delaunay();
  }
  k = curvature(triangulation, metric);
}

// A vertex whose u is far below its neighbours' (at the tip of a spike, away from the cones: the
// linear cone model gives the man's fingertips -6, their neighbours -2 to -3) lies, in the start's
// Delaunay triangulation, inside an edge from one vertex to itself; this triangulation holds no
// such edge (make_delaunay refuses the flip but with FlowOptions::loops, and the one to a face
// around a vertex of degree 1 always), and the jump leaves the faces around that vertex
// invalid. Newton moves every free vertex and converges to one metric whatever its start, so the
// start at those vertices can be eased: each invalid face's corner opposite its longest side
// (the one whose u is too low) is raised until its two sides at it exceed the third by
// kEasingMargin, or where Newton holds that corner, the other two lowered halfway towards it;
// then the jump again. The walk it replaces took CGAL's man 0.28 s of 0.94 at BFF's 8 cones.
// Newton's iterations from the eased start vary with the margin, as from any other start: on the
// five of 20 meshes that ease at 8 cones (CGAL's man, bull, diplodocus, PyMeshLab's cow, CGAL's
// polygon_mesh), the margin 2 took 6, 10, 6, 6, 6 iterations (from the walk 7, 7, 6, 7, 7), and
// the flow 1.07 s in all (1.51 s walking); 1.05 took 6, 8, 11, 6, 6 and 1.24 s; raising the corner
// to the mean of the other two, 6, 12, 8, 7, 6 and 1.19 s. Where Newton stalls from the eased
// start (the tardis's atlas at 29 cones: its steps cut to keep triangles valid at iteration 13),
// the flow goes back and walks to the start as given (finish_walk).
// The easings stop, as hopeless, after this many in a row that leave no fewer invalid faces than
// the fewest before. Where the start is far off, not only at spike tips, they do not converge:
// at BFF's 8 cones occt-tr12j.stl's jumps left 771, 1397, 1531, 1352, 1253, 1407, ... invalid
// faces, CGAL's cheese 16635, 11038, 10018, 12805, 13005, ..., and before this stop all 12
// easings were made (13 jumps of some 10,000 flips each; tr12j now 6) before the walk. Easings
// that end valid went on past a few such, at most four on the real set and CGAL's, one below
// this stop: PrusaSlicer's gmax2 bed 22, 17, 22, 12, 18, 21, 17, 15, 3, 0, CGAL's femur 44, 8, 6,
// 9, 9, 7, 5, 4, 1, 0.
constexpr int kEasings = 12;
constexpr int kEasingsWithoutProgress = 5;
constexpr double kEasingMargin = 2;

Eigen::VectorXd detail::FlowState::jump_eased(const Eigen::VectorXd& start,
                                              detail::LineSearch& jump) {
  Eigen::VectorXd eased = start;
  long fewest_invalid = std::numeric_limits<long>::max();
  for (int easing = 0, since_fewest = 0;; ++easing) {
    detail::evaluate_trial_point(triangulation, structure, eased, true, options.loops, jump);
    ++result.start_jumps;
    if (jump.state.valid() || !jump.flipped || easing == kEasings) return eased;
    const long invalid = std::count_if(jump.state.faces.begin(), jump.state.faces.end(),
                                       [](const auto& face) { return !face.valid; });
    since_fewest = invalid < fewest_invalid ? 0 : since_fewest + 1;
    fewest_invalid = std::min(fewest_invalid, invalid);
    if (since_fewest == kEasingsWithoutProgress) return eased;
    const IntrinsicTriangulation& t = *jump.flipped;
    Eigen::VectorXd next = eased;
    bool moved = false;
    for (int f = 0; f < t.num_faces(); ++f) {
      if (jump.state.faces[f].valid) continue;
      int low = 0;  // the corner opposite the longest side
      for (int c = 1; c < 3; ++c) {
        if (jump.state.edges[t.face_edge(f, c)].length >
            jump.state.edges[t.face_edge(f, low)].length) {
          low = c;
        }
      }
      const int v = t.face_vertex(f, low), a = t.face_vertex(f, (low + 1) % 3),
                b = t.face_vertex(f, (low + 2) % 3);
      if (free_index[v] >= 0) {
        // Its two sides at v grow by exp(delta / 2): long enough for the third, with a margin.
        const double ab = jump.state.edges[t.face_edge(f, low)].length,
                     bv = jump.state.edges[t.face_edge(f, (low + 1) % 3)].length,
                     av = jump.state.edges[t.face_edge(f, (low + 2) % 3)].length;
        next[v] = std::max(next[v], eased[v] + 2 * std::log(kEasingMargin * ab / (av + bv)));
        moved = true;
        continue;
      }
      for (int w : {a, b}) {
        if (free_index[w] < 0) continue;
        next[w] = std::min(next[w], 0.5 * (eased[w] + eased[v]));
        moved = true;
      }
    }
    if (!moved) return eased;
    eased = std::move(next);
  }
}

// Moves u towards `start` in the longest valid steps, flipping to Delaunay after each when flips
// are on. Without them, the walk ends where no step of 1e-6 of the way is valid, or after three
// steps in a row of at most 1/64 of the way; when needed, that is remembered, and the walk made
// again with flips once Newton gets stuck on this triangulation. With them, where the line search
// flips its trial points (every flip a Ptolemy flip; in H2 only after a stall), the start is first
// reached at once as a trial point is. Else, or where that fails (a flip refused, or an invalid
// triangle on the boundary, which no flip mends), the walk ends where no step of 1e-6 of the way
// is valid, or where its steps creep (kCreepingSteps) while the vertices Newton holds are at the
// start's u already, unless `whole_way`.
// The walk's step halves while alpha > 1e-6: the last halving tried is the 19th.
constexpr int kLastHalving = 19;
// With flips, the walk stops after this many steps in a row of at most 1/64 of the way, each at
// most half the one before: they converge to a point short of the start, and flips do not always
// take the walk on from there. Only where every vertex that Newton holds (free_index -1) has the
// start's u already: Newton does not move those, and stopping short elsewhere would change the
// metric it converges to (the atlas's cones and boundary are at u = 0 all the way). At BFF's 8
// cones CGAL's diplodocus walked 30 steps of about 22 ms, its last 12 each half the one before, for
// Newton's 7 iterations; stopped at the third such step, 5 steps and 6 iterations. Stopped at any
// three short steps in a row, occt-tr12j's Newton stalled at iteration 22 (and walked on from
// there, converged at 31; 9 with the whole walk).
constexpr int kCreepingSteps = 3;

// A start that is Newton's first step (FlowOptions::start_is_a_step) is halved at most this many
// times while it does not lower the squared residual (Armijo's test, as search_line's), the
// least residual of those tried taken. The linear cone model overshoots where u is far from 0: at
// BFF's 8 cones CGAL's bull leaves a squared residual of 766 (393 at u = 0), half of it 87, and
// Newton took 10 iterations (8 factorizations) from the whole step, 7 (5) from half. Each
// halving costs a jump (flips and angles, no factorization); past a quarter the start is little
// more than u = 0 (the bull: 216).
constexpr int kStartHalvings = 2;

void detail::FlowState::halve_start(Eigen::VectorXd& start, Eigen::VectorXd& eased,
                                    detail::LineSearch& jump) {
  const Eigen::VectorXd whole = start;
  bool moves = false;  // a start of the flow's u (user cones, an unfolding: u = 0) is no step
  for (int v = 0; v < static_cast<int>(u.size()) && !moves; ++v) {
    moves = free_index[v] >= 0 && whole[v] != u[v];
  }
  if (!moves) return;
  const int n = steps.num_free();
  const auto merit = [&](const detail::LineSearch& at) {
    const Eigen::VectorXd k_at = curvature(at.flipped ? *at.flipped : triangulation, at.state);
    return 0.5 * detail::free_residual(k_at, goal, free_index, n).squaredNorm();
  };
  const double here =
      0.5 *
      detail::free_residual(curvature(triangulation, metric), goal, free_index, n).squaredNorm();
  double share = 1, least = merit(jump);
  for (int halving = 0; halving < kStartHalvings && !(least <= (1 - 1e-4 * share) * here);
       ++halving) {
    share /= 2;
    Eigen::VectorXd nearer = whole;
    for (int v = 0; v < static_cast<int>(u.size()); ++v) {
      if (free_index[v] >= 0) nearer[v] = u[v] + share * (whole[v] - u[v]);
    }
    detail::LineSearch trial;
    Eigen::VectorXd trial_eased = jump_eased(nearer, trial);
    if (!trial.state.valid()) continue;
    const double phi = merit(trial);
    if (!(phi < least)) continue;
    least = phi;
    result.start_share = share;
    start = std::move(nearer);
    eased = std::move(trial_eased);
    jump = std::move(trial);
  }
}

void detail::FlowState::walk_to(const Eigen::VectorXd& start, bool whole_way, bool ease) {
  if (!start.allFinite()) return;
  if (flipping && all_ptolemy(structure) && (!hyperbolic() || flip_trial_points)) {
    // The whole way at once: the start's Delaunay triangulation by Ptolemy flips from the
    // lengths, valid whatever u (delaunay.h), unless a flip was refused there or a boundary
    // triangle is invalid.
    detail::LineSearch jump;
    Eigen::VectorXd eased = ease ? jump_eased(start, jump) : start;
    if (!ease) {
      detail::evaluate_trial_point(triangulation, structure, start, true, options.loops, jump);
      ++result.start_jumps;
    }
    Eigen::VectorXd taken = start;  // the start, or the share of it halve_start takes
    if (ease && options.start_is_a_step && jump.state.valid() && metric.valid()) {
      halve_start(taken, eased, jump);
    }
    if (jump.state.valid()) {
      result.eased_start_vertices = static_cast<int>((eased.array() != taken.array()).count());
      if (result.eased_start_vertices > 0) unfinished_walk = walk_from_here(taken, true);
      if (jump.flipped) adopt_flips(jump);
      u = eased;
      metric = std::move(jump.state);
      keep_delaunay();
      return;
    }
  }
  const Eigen::VectorXd origin = u;
  bool held_at_start = true;
  for (int v = 0; v < static_cast<int>(u.size()) && held_at_start; ++v) {
    held_at_start = free_index[v] >= 0 || u[v] == start[v];
  }
  int short_steps = 0, creeping = 0;
  double last_alpha = 1;
  for (int step = 0; step < 200; ++step) {
    const Eigen::VectorXd d = start - u;
    double alpha = 1;
    MetricState trial = evaluate_lengths(triangulation, structure, u + d);
    bool found = false;
    // Most trials are cut (the cow's atlas at 8 cones: 27 steps of up to 17 halvings each), and
    // their triangle inequalities decide it without the angles. The halvings that some face
    // fails alone are skipped, each face tried alone (first_halving_admitted); from there the
    // halvings are tried on the whole mesh as before.
    bool evaluated = true;  // trial holds the lengths at alpha
    if (!lengths_admit_triangles(triangulation, structure.geometry, trial)) {
      // The whole step failed: at least one halving (first_halving_admitted is 0 outside the
      // plane).
      const int skip = first_halving_admitted(triangulation, structure, u, d, trial, kLastHalving);
      alpha = std::ldexp(1.0, -std::max(skip, 1));
      evaluated = false;
    }
    for (; alpha > 1e-6; alpha *= 0.5, evaluated = false) {
      if (!evaluated) trial = evaluate_lengths(triangulation, structure, u + alpha * d);
      if (!lengths_admit_triangles(triangulation, structure.geometry, trial)) continue;
      evaluate_angles(triangulation, structure.geometry, trial);
      if (trial.valid()) {
        found = true;
        break;
      }
    }
    // Without flips, steps that stay short only creep along the valid set's boundary.
    short_steps = alpha <= detail::kShortStep ? short_steps + 1 : 0;
    if (!found || (!flipping && short_steps > detail::StallWindow::kLengthBeforeFlips)) {
      if (may_start_flipping()) blocked_walk.emplace(origin, start);
      return;
    }
    u += alpha * d;
    metric = std::move(trial);
    keep_delaunay();
    if (alpha == 1) return;
    // With flips, steps each at most half the one before converge short of the start: Newton goes
    // on from there, and the walk is made the whole way only if Newton stalls (run()).
    creeping = alpha <= detail::kShortStep && alpha <= 0.5 * last_alpha ? creeping + 1 : 0;
    last_alpha = alpha;
    if (flipping && !whole_way && held_at_start && creeping >= kCreepingSteps) {
      unfinished_walk = walk_from_here(start, false);
      return;
    }
  }
}

detail::FlowState::UnfinishedWalk detail::FlowState::walk_from_here(const Eigen::VectorXd& start,
                                                                    bool eased) const {
  return UnfinishedWalk{start,
                        u,
                        triangulation,
                        structure.eta,
                        metric,
                        flip_sequence.size(),
                        result.num_flips,
                        result.connectivity_changes,
                        result.loops_refused,
                        eased};
}

void detail::FlowState::finish_walk() {
  UnfinishedWalk w = std::move(*unfinished_walk);
  unfinished_walk.reset();
  u = std::move(w.u);
  triangulation = std::move(w.triangulation);
  structure.eta = std::move(w.eta);
  metric = std::move(w.metric);
  flip_sequence.resize(w.flips_made);
  result.num_flips = w.num_flips;
  result.connectivity_changes = w.connectivity_changes;
  result.loops_refused = w.loops_refused;
  steps.set_pattern(triangulation, free_index, flip_sequence.empty());
  if (w.eased) result.eased_start_vertices = 0;
  walk_to(w.start, !w.eased, false);
  k = curvature(triangulation, metric);
  stall = detail::StallWindow();
  lm_weight = 1;
  newton_start = u;
  start_round_off = curvature_round_off(triangulation, metric).maxCoeff();
}

}  // namespace ricci
