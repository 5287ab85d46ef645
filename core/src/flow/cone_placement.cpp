#include "ricci/flow/cone_placement.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <tuple>
#include <utility>

#include "flow/constrained_quadratic.h"
#include "flow/held_system.h"
#include "flow/linear_cone_model.h"
#include "mesh/clock.h"
#include "ricci/mesh/errors.h"

namespace ricci {

namespace {

// Where a cone moves in a Gauss-Seidel sweep: the best of this many peaks of |u| of the set
// without it (local maxima, largest first), when the budget stops the greedy. One (CEPS's argmax)
// leaves D at budget 8 at 1.72 on a cow, 0.29 on a genus-4 flange, 0.51 on a bunny; 6 at 1.13,
// 0.27, 0.46, for about 5 times the sweeps' back-solves.
constexpr int kRelocationCandidates = 6;

// Columns kept besides the cones' for the candidates tried lately (a sweep's candidates for one
// cone are mostly those for the next), at most this many bytes of them, and at most a sweep's
// candidates for about ten cones (each column kept costs a product per column solved later).
constexpr double kSpareColumnBytes = 128.0 * 1024 * 1024;
constexpr int kMaxSpareColumns = 64;
// Columns solved in one block at most: the factor is read once a block, and past 32 columns a
// column costs little less (bench_atlas: 1.8 ms at 32, 2.4 at 8, 5.9 alone on a bunny), while the
// block's dense right-hand sides grow with it.
constexpr size_t kMaxBlock = 32;
// A sweep's u without each cone solved ahead, this many cones at first and after a move, twice as
// many (up to kMaxBlock) after a block read to its end.
constexpr size_t kMinAhead = 4;
// From this many cones a set that differs from the current one by a cone is solved from the
// current one's inverse (HeldSystem, O(|C|^2)) instead of factored (O(|C|^3)): at a few hundred
// cones the factorizations were most of the placement (CGAL's cheese, genus 133).
constexpr size_t kIncrementalFrom = 16;
// A cone that would open a corner of its faces past a half turn (no triangle has such a corner)
// is moved within kWideMoveRings rings to a vertex where it opens none past kDrawableCorner (a
// margin for the estimate: the bull's was 3.48 for a corner of 3.73), where no other cone comes
// to open one past a half turn, its D within kWideMoveSlack of the set's before any such move.
// Measured at 8 cones (D of the exact metric): CGAL's bull 1.366 to 1.285 and man 1.534 to
// 1.538, both then on their own faces; within one ring and 2 %, the bull's two cones found one
// move, within 2 rings and 5 % both.
constexpr double kDrawableCorner = 0.9 * kPi;
constexpr double kWideMoveSlack = 0.05;
constexpr int kWideMoveRings = 2;
// A vertex whose own angle sum (in 3D) is below twice the floor may have a cone down to this share
// of that sum: its wedge is then its own faces, their corners at least this share of their own.
constexpr double kOwnAngleShare = 0.5;
// Quarter-turn cones: the moves of a quarter turn of curvature tried after the rounding, at most,
// each among this many vertices of lowest and of highest u.
constexpr int kQuarterMoves = 200;
constexpr size_t kQuarterCandidates = 8;

// The placement's search: a cone set, its solution and D.
class Search {
 public:
  Search(const CompactMesh& mesh, const ConePlacementOptions& o)
      : mesh_(mesh),
        o_(o),
        model_(mesh, o.linear_solver, static_cast<size_t>(o.u_solved_from)),
        system_(model_) {
    is_cone_.assign(mesh.num_vertices(), 0);
    first_neighbour_.assign(mesh.num_vertices() + 1, 0);
    for (int e = 0; e < mesh.num_edges(); ++e) {
      for (int v : mesh.edge_vertices(e)) ++first_neighbour_[v + 1];
    }
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      first_neighbour_[v + 1] += first_neighbour_[v];
      if (mesh.is_boundary_vertex(v)) boundary_.push_back(v);
    }
    neighbour_.resize(first_neighbour_.back());
    std::vector<int> fill(first_neighbour_.begin(), first_neighbour_.end() - 1);
    for (int e = 0; e < mesh.num_edges(); ++e) {
      const auto [a, b] = mesh.edge_vertices(e);
      neighbour_[fill[a]++] = b, neighbour_[fill[b]++] = a;
    }
    // Per vertex, its widest corner and its angle sum among the input's faces (in 3D).
    widest_corner_.assign(mesh.num_vertices(), 0);
    angle_sum_.assign(mesh.num_vertices(), 0);
    const auto& p = mesh.positions();
    for (const auto& t : mesh.faces()) {
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d a = p[t[(k + 1) % 3]] - p[t[k]], b = p[t[(k + 2) % 3]] - p[t[k]];
        const double corner = angle_between(a, b);
        widest_corner_[t[k]] = std::max(widest_corner_[t[k]], corner);
        angle_sum_[t[k]] += corner;
      }
    }
    floor_.resize(mesh.num_vertices());
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      floor_[v] = std::min(o.min_cone_angle, kOwnAngleShare * angle_sum_[v]);
    }
    max_spare_ = static_cast<size_t>(std::clamp(
        kSpareColumnBytes / (8.0 * std::max(1, mesh.num_vertices())), 1.0, 1.0 * kMaxSpareColumns));
  }

  LinearConeModel& model() { return model_; }

  // The columns of these vertices, solved together where missing, and kept as spare ones.
  void solve_columns(const std::vector<int>& vertices) {
    model_.solve_columns(vertices);
    for (auto v = vertices.rbegin(); v != vertices.rend(); ++v) {
      spare_.erase(std::remove(spare_.begin(), spare_.end(), *v), spare_.end());
      spare_.insert(spare_.begin(), *v);
    }
    if (spare_.size() > max_spare_) spare_.resize(max_spare_);
  }
  // Every column but the cones' and the spare ones dropped (n doubles each).
  void keep_columns(const std::vector<int>& cones) {
    std::vector<int> kept = cones;
    kept.insert(kept.end(), spare_.begin(), spare_.end());
    model_.keep_only(kept);
  }

  struct State {
    std::vector<int> cones;
    LinearConeModel::Solution solution;
    double d = std::numeric_limits<double>::infinity();
    bool angles_ok = false;
  };
  State evaluate(std::vector<int> cones) {
    LinearConeModel::Solution solution = model_.held(cones);
    return state_of(std::move(cones), std::move(solution));
  }
  State state_of(std::vector<int> cones, LinearConeModel::Solution solution) const {
    State s;
    s.cones = std::move(cones);
    s.solution = std::move(solution);
    if (!s.solution.ok) return s;
    s.d = s.solution.d;
    s.angles_ok = angles_ok(s.cones, s.solution.k);
    return s;
  }
  // Whether every cone of curvature k is within its floor.
  bool angles_ok(const std::vector<int>& cones, const Eigen::VectorXd& k) const {
    for (size_t i = 0; i < cones.size(); ++i) {
      if (!(k[static_cast<long>(i)] <= 2 * kPi - floor_[cones[i]])) return false;
    }
    return true;
  }
  // The set s with v added last, with its i-th cone moved to v (moved = i), or without its i-th
  // cone (v < 0): from s's held system where s has many cones.
  State step(const State& s, int v, int moved = -1) {
    const size_t m = s.cones.size();
    std::vector<int> cones = cone_set_step(s.cones, v, moved);
    if (m < kIncrementalFrom || !s.solution.ok) return evaluate(std::move(cones));
    if (!system_.valid() || system_.cones() != s.cones) system_.reset(s.cones);
    if (!system_.valid()) return evaluate(std::move(cones));
    LinearConeModel::Solution solution = v < 0 ? system_.without(moved) : system_.with(v, moved);
    // A set the held system finds singular is factored afresh: the verdict is held()'s.
    if (!solution.ok) return evaluate(std::move(cones));
    return state_of(std::move(cones), std::move(solution));
  }
  // The held system follows the search to t, a step from s as `step` took it; t then has the
  // system's solution (refined at its checks of drift, or after a fresh factorization).
  void follow(const State& s, State& t, int v, int moved = -1) {
    if (s.cones.size() < kIncrementalFrom || !system_.valid() || system_.cones() != s.cones) return;
    if (v < 0) {
      system_.remove(moved);
    } else {
      system_.add(v, moved);
    }
    if (system_.cones() != t.cones) system_.reset(t.cones);
    if (system_.valid()) t = state_of(t.cones, system_.solution());
  }
  bool done(const State& s) const { return s.solution.ok && s.angles_ok && s.d <= bound(); }
  double bound() const { return o_.distortion_bound; }

  // The interior vertices, not cones, where |u| (|u - mean| without cones) peaks over their
  // neighbours, largest first, at most `count`; the first is the farthest vertex. u is s's, given
  // or computed here.
  std::vector<int> peaks(const State& s, int count, const Eigen::VectorXd* given = nullptr) {
    if (!s.solution.ok) return {};
    Eigen::VectorXd own;
    if (!given) own = model_.u(s.cones, s.solution);
    const Eigen::VectorXd& u = given ? *given : own;
    const double mean = s.cones.empty() ? model_.area().dot(u) : 0;
    // |u - mean| where a cone may go, -1 where none may (a cone, the boundary): a vertex is a
    // peak over the neighbours that could be cones themselves.
    score_ = (u.array() - mean).abs();
    for (int v : boundary_) score_[v] = -1;
    for (int c : s.cones) score_[c] = -1;
    if (count == 1) {  // the largest is a peak: no neighbour to compare (ties to the last vertex)
      std::pair<double, int> top(-1, -1);
      for (int v = 0; v < mesh_.num_vertices(); ++v) top = std::max(top, {score_[v], v});
      return top.first >= 0 ? std::vector<int>{top.second} : std::vector<int>{};
    }
    std::vector<std::pair<double, int>> found;
    for (int v = 0; v < mesh_.num_vertices(); ++v) {
      const double d = score_[v];
      if (d < 0) continue;
      bool peak = true;
      for (int i = first_neighbour_[v]; i < first_neighbour_[v + 1] && peak; ++i) {
        peak = score_[neighbour_[i]] <= d;
      }
      if (peak) found.emplace_back(d, v);
    }
    const size_t kept = std::min(found.size(), static_cast<size_t>(count));
    std::partial_sort(found.begin(), found.begin() + static_cast<long>(kept), found.end(),
                      std::greater<>());
    std::vector<int> vertices;
    for (size_t i = 0; i < kept; ++i) vertices.push_back(found[i].second);
    return vertices;
  }
  // u of s without its i-th cone, where a set of that size has its u solved for (else null, and
  // peaks sums it from the columns): solved together with those without each of the next cones,
  // which stay valid while s does (forget_ahead when it changes). A sweep that moves no cone then
  // reads the factor once per block instead of once per cone.
  const Eigen::VectorXd* u_without(const State& s, size_t i) {
    const size_t m = s.cones.size();
    if (m < 2 || !s.solution.ok || !model_.u_by_solve(m - 1)) return nullptr;
    if (i >= ahead_from_ && i < ahead_from_ + ahead_.size()) {
      const Eigen::VectorXd& u = ahead_[i - ahead_from_];
      return u.size() > 0 ? &u : nullptr;
    }
    if (i == ahead_from_ + ahead_.size() && !ahead_.empty()) {  // the last block all read
      ahead_block_ = std::min(kMaxBlock, 2 * ahead_block_);
    }
    const size_t count = std::min({ahead_block_, m - i, max_spare_});
    std::vector<State> rests;
    std::vector<std::vector<int>> sets;
    std::vector<const LinearConeModel::Solution*> solutions;
    for (size_t j = i; j < i + count; ++j) rests.push_back(step(s, -1, static_cast<int>(j)));
    for (const State& r : rests) {
      if (r.solution.ok) sets.push_back(r.cones), solutions.push_back(&r.solution);
    }
    std::vector<Eigen::VectorXd> us;
    if (!sets.empty()) us = model_.u(sets, solutions);
    ahead_.assign(count, Eigen::VectorXd());
    for (size_t j = 0, k = 0; j < count; ++j) {
      if (rests[j].solution.ok) ahead_[j] = std::move(us[k++]);
    }
    ahead_from_ = i;
    return ahead_[0].size() > 0 ? &ahead_[0] : nullptr;
  }
  // The set changed (a cone moved): the u solved ahead are no longer its; the next block smaller.
  void forget_ahead() {
    if (!ahead_.empty()) ahead_block_ = std::max(kMinAhead, ahead_block_ / 2);
    ahead_.clear();
    ahead_from_ = 0;
  }

  // The widest corner of v's faces with a cone of angle theta at v, as the flat metric opens it:
  // near the cone every corner by about theta over v's angle sum.
  double opened_corner(int v, double theta) const {
    return widest_corner_[v] * theta / angle_sum_[v];
  }
  // The widest corner that s's i-th cone opens.
  double opened_corner(const State& s, size_t i) const {
    return opened_corner(s.cones[i], 2 * kPi - s.solution.k[static_cast<long>(i)]);
  }
  // The columns of these vertices, in blocks of at most kMaxBlock (their right-hand sides are
  // dense); kept as spare ones where `spare`, else dropped with the next cone kept.
  void solve_in_blocks(const std::vector<int>& vertices, bool spare) {
    for (size_t i = 0; i < vertices.size(); i += kMaxBlock) {
      const std::vector<int> block(
          vertices.begin() + static_cast<long>(i),
          vertices.begin() + static_cast<long>(std::min(vertices.size(), i + kMaxBlock)));
      if (spare) {
        solve_columns(block);
      } else {
        model_.solve_columns(block);
      }
    }
  }
  // The vertices within `depth` rings of v where a cone may go (not a cone of s, not on the
  // boundary), v's own excluded.
  std::vector<int> free_within(const State& s, int v, int depth) {
    mark(s.cones);
    std::vector<int> found;
    for (int w : rings(v, depth)) {
      if (!is_cone_[w] && !mesh_.is_boundary_vertex(w)) found.push_back(w);
    }
    unmark(s.cones);
    return found;
  }
  // The least margin of s's cone angles over their floors (negative where one is sharper), and
  // the cone that has it.
  double angle_margin(const State& s, int* at = nullptr) const {
    double least = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < s.cones.size(); ++i) {
      const double margin = 2 * kPi - s.solution.k[static_cast<long>(i)] - floor_[s.cones[i]];
      if (margin < least) {
        least = margin;
        if (at) *at = static_cast<int>(i);
      }
    }
    return least;
  }
  // Near the cone farthest below its floor (two rings), the vertex whose cone leaves the least
  // margin over the floors widest.
  int widen_sharpest(const State& s) {
    int sharpest = 0;
    angle_margin(s, &sharpest);
    mark(s.cones);
    std::vector<int> tried_there;
    for (int v : rings(s.cones[sharpest], 2)) {
      if (!is_cone_[v] && !mesh_.is_boundary_vertex(v)) tried_there.push_back(v);
    }
    solve_in_blocks(tried_there, false);
    int best = -1;
    double widest = -std::numeric_limits<double>::infinity();
    for (int v : tried_there) {
      const State t = step(s, v);
      if (!t.solution.ok) continue;
      const double margin = angle_margin(t);
      if (margin > widest) widest = margin, best = v;
    }
    unmark(s.cones);
    return best;
  }

  // The curvatures of s's cones that minimize D, u free at the cones: within each cone's floor,
  // opening no corner past kDrawableCorner, and u - mean u at each cone within the range s's u
  // spans (freed of its range, D would fall further by squeezing small protrusions: a camel's
  // hoof to e^-13 at 8 cones, D 1.68 to 1.41); where s's own curvatures (u held at 0 at the
  // cones) pass these, up to them.
  Eigen::VectorXd least_distortion(const State& s) {
    const Eigen::VectorXd& k = s.solution.k;
    const long m = k.size();
    ConstrainedQuadratic p;
    std::tie(p.q, p.b) = model_.distortion_form(s.cones);
    p.q = (p.q + p.q.transpose()) / 2;
    p.sum_fixed = mesh_.is_closed();
    const Eigen::VectorXd u = model_.u(s.cones, s.solution);
    const Eigen::VectorXd& area = model_.area();
    const double mean = area.dot(u);
    const double low = u.minCoeff() - mean, high = u.maxCoeff() - mean;
    const double g_mean = area.dot(model_.g());
    p.a = Eigen::MatrixXd::Zero(4 * m, m);
    p.limit.resize(4 * m);
    for (long i = 0; i < m; ++i) {
      const int v = s.cones[static_cast<size_t>(i)];
      p.a(i, i) = 1;
      p.limit[i] = std::max(k[i], 2 * kPi - floor_[v]);
      p.a(m + i, i) = -1;
      p.limit[m + i] =
          -std::min(k[i], 2 * kPi - kDrawableCorner * angle_sum_[v] / widest_corner_[v]);
      // u_v - mean u = g_v - mean g + sum_j k_j (col_j[v] - mean col_j).
      for (long j = 0; j < m; ++j) {
        const int c = s.cones[static_cast<size_t>(j)];
        p.a(2 * m + i, j) = model_.entry(v, c) - model_.column_sum(c);
      }
      p.a.row(3 * m + i) = -p.a.row(2 * m + i);
      const double offset = model_.g()[v] - g_mean;
      p.limit[2 * m + i] = std::max(high, u[v] - mean) - offset;
      p.limit[3 * m + i] = -std::min(low, u[v] - mean) + offset;
    }
    return minimize_constrained(p, k);
  }

  // Quarter-turn cones (k their curvatures) whose rounding left D above the bound: a quarter turn
  // of curvature moved at a time, from the vertex where u is highest to where it is lowest (a
  // cone made, grown or dropped there; on a surface with boundary, whose boundary takes up the
  // difference, one end alone too), the move among the kQuarterCandidates lowest minima and
  // highest maxima of u that lowers D most, while D is above the bound and one does; each cone
  // within its floor and drawable (kDrawableCorner), at most `budget` cones.
  void move_quarters(std::vector<int>& cones, Eigen::VectorXd& k, int budget) {
    const double quarter = kPi / 2;
    const bool closed = mesh_.is_closed();
    for (int round = 0; round < kQuarterMoves; ++round) {
      keep_columns(cones);  // the last round's candidates' dropped: n doubles each
      solve_in_blocks(cones, false);
      const double d = model_.distortion(cones, k);
      if (d <= bound()) return;
      const Eigen::VectorXd u = model_.prescribed(cones, k);
      // The interior vertices where u is lowest of their neighbours, and where highest.
      std::vector<int> low, high;
      for (int v = 0; v < mesh_.num_vertices(); ++v) {
        if (mesh_.is_boundary_vertex(v)) continue;
        bool lowest = true, highest = true;
        for (int i = first_neighbour_[v]; i < first_neighbour_[v + 1]; ++i) {
          lowest = lowest && u[v] <= u[neighbour_[i]];
          highest = highest && u[v] >= u[neighbour_[i]];
        }
        if (lowest) low.push_back(v);
        if (highest) high.push_back(v);
      }
      const auto keep = [&](std::vector<int>& ends, double sign) {
        const size_t n = std::min(kQuarterCandidates, ends.size());
        std::partial_sort(ends.begin(), ends.begin() + static_cast<long>(n), ends.end(),
                          [&](int a, int b) { return sign * u[a] < sign * u[b]; });
        ends.resize(n);
      };
      keep(low, 1);
      keep(high, -1);
      if (closed ? low.empty() || high.empty() : low.empty() && high.empty()) return;
      std::vector<int> candidates = low;
      candidates.insert(candidates.end(), high.begin(), high.end());
      solve_in_blocks(candidates, false);
      // The cones with a quarter more at `up` and a quarter less at `down` (-1: none), or none
      // where a cone would pass its floor or open a corner past kDrawableCorner, or exceed the
      // budget.
      const auto moved = [&](int up, int down, std::vector<int>& c, Eigen::VectorXd& kc) {
        c = cones;
        std::vector<double> kk(k.data(), k.data() + k.size());
        for (const auto& [v, change] : {std::pair{up, quarter}, std::pair{down, -quarter}}) {
          if (v < 0) continue;
          const auto at = std::find(c.begin(), c.end(), v);
          const size_t i = static_cast<size_t>(at - c.begin());
          if (at == c.end()) c.push_back(v), kk.push_back(0);
          kk[i] += change;
          const double theta = 2 * kPi - kk[i];
          if (std::abs(kk[i]) < quarter / 2) {
            c.erase(c.begin() + static_cast<long>(i)), kk.erase(kk.begin() + static_cast<long>(i));
          } else if (theta < floor_[v] || opened_corner(v, theta) > kDrawableCorner) {
            return false;
          }
        }
        if (static_cast<int>(c.size()) > budget) return false;
        kc = Eigen::Map<Eigen::VectorXd>(kk.data(), static_cast<long>(kk.size()));
        return true;
      };
      double best = d;
      bool found = false;
      std::vector<int> best_cones, c;
      Eigen::VectorXd best_k, kc;
      const auto consider = [&](int up, int down) {
        if (!moved(up, down, c, kc)) return;
        const double dc = model_.distortion(c, kc);
        if (dc < best) best = dc, best_cones = c, best_k = kc, found = true;
      };
      for (int up : low) {
        for (int down : high) consider(up, down);
        if (!closed) consider(up, -1);
      }
      if (!closed) {
        for (int down : high) consider(-1, down);
      }
      if (!found) return;
      cones = std::move(best_cones);
      k = std::move(best_k);
    }
  }

 private:
  void mark(const std::vector<int>& cones) {
    for (int c : cones) is_cone_[c] = 1;
  }
  void unmark(const std::vector<int>& cones) {
    for (int c : cones) is_cone_[c] = 0;
  }
  std::vector<int> rings(int from, int depth) const {
    std::vector<int> found{from}, frontier{from};
    for (int d = 0; d < depth; ++d) {
      std::vector<int> next;
      for (int v : frontier) {
        for (int i = first_neighbour_[v]; i < first_neighbour_[v + 1]; ++i) {
          const int w = neighbour_[i];
          if (std::find(found.begin(), found.end(), w) == found.end()) {
            found.push_back(w), next.push_back(w);
          }
        }
      }
      frontier = std::move(next);
    }
    return found;
  }

  const CompactMesh& mesh_;
  ConePlacementOptions o_;
  LinearConeModel model_;
  HeldSystem system_;  // the current set's, where it has many cones
  std::vector<char> is_cone_;
  std::vector<int> spare_;  // most recently solved first
  size_t max_spare_ = 1;
  std::vector<int> boundary_, first_neighbour_, neighbour_;  // the neighbours of v: CSR
  std::vector<double> widest_corner_, angle_sum_;
  std::vector<double> floor_;  // per vertex, the sharpest cone it may have
  Eigen::VectorXd score_;
  // u without each of the cones from ahead_from_ on (empty: that set singular), as u_without
  // solved them; ahead_block_ of them solved at a time.
  std::vector<Eigen::VectorXd> ahead_;
  size_t ahead_from_ = 0, ahead_block_ = kMinAhead;
};

// Curvatures rounded to multiples of pi / 2, their sum kept on a closed surface (4 chi quarters),
// none above 2 pi - the floor.
Eigen::VectorXd quarter_rounded(const Eigen::VectorXd& k, bool closed, int chi, double min_angle) {
  const double quarter = kPi / 2;
  const int top = static_cast<int>(std::floor((2 * kPi - min_angle) / quarter + 1e-9));
  Eigen::VectorXi q(k.size());
  for (int i = 0; i < k.size(); ++i) {
    q[i] = std::min(top, static_cast<int>(std::lround(k[i] / quarter)));
  }
  if (closed) {
    // Move the cones rounded farthest from their value by one quarter each, towards it.
    int missing = 4 * chi - q.sum();
    std::vector<int> order(k.size());
    std::iota(order.begin(), order.end(), 0);
    const int sign = missing > 0 ? 1 : -1;
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return sign * (k[a] / quarter - q[a]) > sign * (k[b] / quarter - q[b]);
    });
    // Rounds over the cones until the sum is met, or a whole round changes none (every cone at
    // the floor's limit: the sum is then left short, and D says what that costs).
    bool changed = true;
    while (missing != 0 && changed) {
      changed = false;
      for (size_t j = 0; j < order.size() && missing != 0; ++j) {
        const int i = order[j];
        if (sign > 0 && q[i] >= top) continue;
        q[i] += sign;
        missing -= sign;
        changed = true;
      }
    }
  }
  return q.cast<double>() * quarter;
}

}  // namespace

double area_distortion(const CompactMesh& mesh, const Eigen::VectorXd& u) {
  return area_weighted_deviation(normalized_vertex_areas(mesh), u);
}

ConePlacement place_cones(const CompactMesh& mesh, const ConePlacementOptions& o) {
  if (!(o.distortion_bound > 0) || o.max_cones < 0 || !(o.min_cone_angle > 0) ||
      !(o.min_cone_angle < 2 * kPi) || o.relocation_sweeps < 0 || o.u_solved_from < 0) {
    throw InvalidArgumentError(
        "cone placement: the distortion bound and the cone floor must be positive (the floor "
        "below 2 pi), the budget, the sweeps and u_solved_from non-negative");
  }
  const auto started = detail::Clock::now();
  const int budget = cone_budget(o);
  Search search(mesh, o);
  LinearConeModel& model = search.model();
  ConePlacement result;
  const bool closed = mesh.is_closed();
  const int chi = mesh.euler_characteristic();
  result.distortion_without_cones = std::numeric_limits<double>::quiet_NaN();
  if (!closed || chi == 0) {
    result.distortion_without_cones = search.evaluate({}).d;
  }

  // === Greedy: from the curvature extremum (closed, chi != 0), add the farthest vertex.
  std::vector<int> start;
  if (closed && chi != 0) {
    int v = 0;
    if (chi > 0) {
      model.curvature0().maxCoeff(&v);
    } else {
      model.curvature0().minCoeff(&v);
    }
    start.push_back(v);
  }
  Search::State state = search.evaluate(start);
  while (!search.done(state) && static_cast<int>(state.cones.size()) < budget) {
    int v = -1;
    if (state.solution.ok && state.d <= search.bound()) v = search.widen_sharpest(state);
    if (v < 0) {
      const std::vector<int> top = search.peaks(state, 1);
      if (top.empty()) break;
      v = top.front();
    }
    Search::State more = search.step(state, v);
    search.follow(state, more, v);
    state = std::move(more);
    search.keep_columns(state.cones);
  }

  // === Gauss-Seidel: each cone moved to the best peak of |u| of the set without it (CEPS moves
  // it to the argmax). Where the greedy stopped short of the bound (at the budget, or for want of
  // a vertex), the best of several peaks; else the argmax alone: the sweeps then cost what the
  // greedy does, and the cones they leave give fewer overlapping charts (a genus-4 flange: 23
  // charts against 39 without sweeps).
  // A cone tried again with no cone moved since it was last tried finds what it found then: the
  // sweeps stop once every cone has been tried in a row without a move.
  const int candidates = search.done(state) ? 1 : kRelocationCandidates;
  size_t tried_since_move = 0;
  for (int sweep = 0; sweep < o.relocation_sweeps && !state.cones.empty(); ++sweep) {
    int moved = 0;
    for (size_t i = 0; i < state.cones.size(); ++i, ++tried_since_move) {
      if (tried_since_move >= state.cones.size()) break;
      const int at = static_cast<int>(i);
      const Search::State rest = search.step(state, -1, at);
      if (!rest.solution.ok) continue;
      Search::State best = state;
      int best_v = -1;
      const std::vector<int> moves = search.peaks(rest, candidates, search.u_without(state, i));
      search.solve_columns(moves);
      for (int v : moves) {
        if (v == state.cones[i]) continue;
        const Search::State trial = search.step(state, v, at);
        const bool better = trial.solution.ok && (trial.angles_ok || !best.angles_ok) &&
                            trial.d < best.d * (1 - 1e-9);
        if (better) best = trial, best_v = v;
      }
      if (best_v >= 0) {
        search.forget_ahead();
        search.follow(state, best, best_v, at);
        state = std::move(best);
        ++moved;
        tried_since_move = 0;
      }
      search.keep_columns(state.cones);
    }
    result.relocations += moved;
    if (tried_since_move >= state.cones.size()) break;
  }

  // === The weakest cones dropped while the bound and the floor hold.
  if (search.done(state)) {
    std::vector<int> order(state.cones.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return std::abs(state.solution.k[a]) < std::abs(state.solution.k[b]);
    });
    std::vector<int> drop;
    for (int i : order) drop.push_back(state.cones[i]);
    for (int c : drop) {
      const int at = static_cast<int>(std::find(state.cones.begin(), state.cones.end(), c) -
                                      state.cones.begin());
      Search::State trial = search.step(state, -1, at);
      if (search.done(trial)) {
        search.follow(state, trial, -1, at);
        state = std::move(trial);
        ++result.dropped;
      }
    }
  }

  // === Cones that would open a corner of their faces past a half turn moved to a vertex nearby
  // where they open none past kDrawableCorner and no other cone comes to open one past a half turn,
  // the one of least D, where D stays within kWideMoveSlack of the set's before these moves (and
  // the bound and the angle floor, where they held). Such a corner cannot be drawn as the corner of
  // one triangle: on the user's own faces the atlas would turn that face over (CGAL's bull at 8
  // cones: two cones of 12 rad at vertices of five faces with corners of 115 and 102 degrees,
  // corners of 3.7 and 3.9 rad).
  if (state.solution.ok) {
    const double d_before = state.d;
    for (size_t i = 0; i < state.cones.size(); ++i) {
      if (!(search.opened_corner(state, i) > kPi)) continue;
      const double theta = 2 * kPi - state.solution.k[static_cast<long>(i)];
      std::vector<int> moves;
      for (int v : search.free_within(state, state.cones[i], kWideMoveRings)) {
        if (search.opened_corner(v, theta) <= kDrawableCorner) moves.push_back(v);
      }
      search.solve_in_blocks(moves, true);
      Search::State best;
      int best_v = -1;
      const bool was_done = search.done(state);
      for (int v : moves) {
        Search::State trial = search.step(state, v, static_cast<int>(i));
        if (!trial.solution.ok || (was_done && !search.done(trial)) ||
            (state.angles_ok && !trial.angles_ok) ||
            !(trial.d <= (1 + kWideMoveSlack) * d_before) || !(trial.d < best.d) ||
            !(search.opened_corner(trial, i) <= kDrawableCorner)) {
          continue;
        }
        bool others_drawable = true;
        for (size_t j = 0; j < trial.cones.size() && others_drawable; ++j) {
          others_drawable = j == i || search.opened_corner(trial, j) <= kPi ||
                            search.opened_corner(state, j) > kPi;
        }
        if (others_drawable) best = std::move(trial), best_v = v;
      }
      if (best_v >= 0) {
        search.follow(state, best, best_v, static_cast<int>(i));
        state = std::move(best);
        ++result.relocations;
      }
      search.keep_columns(state.cones);
    }
  }

  // === Where the bound was not reached: the curvatures of least D for these cones. u is then
  // free at them (held at 0 there, the greedy's model, it is not the least D the cones allow),
  // each cone within its floor and drawable where the held one was. Not where the bound was
  // reached: there the held model's curvatures stand (the default atlases are as before).
  Eigen::VectorXd k = state.solution.k;
  if (o.least_distortion_angles && state.solution.ok && !search.done(state) &&
      !state.cones.empty() && static_cast<int>(state.cones.size()) <= kLeastDistortionCones) {
    const Eigen::VectorXd least = search.least_distortion(state);
    const double d = model.distortion(state.cones, least);
    if (d < state.d * (1 - 1e-9)) {
      k = least, state.d = d;
      state.angles_ok = search.angles_ok(state.cones, k);
      result.least_distortion = true;
    }
  }

  Eigen::VectorXd u;
  if (result.least_distortion) {
    u = model.prescribed(state.cones, k);
  } else if (state.solution.ok) {
    u = model.u(state.cones, state.solution);
  }
  // No flat metric with these cones (a singular system): none are delivered, and the flow says
  // what the target without them gives.
  std::vector<int> cones = state.solution.ok ? state.cones : std::vector<int>{};
  if (o.quarter_angles && state.solution.ok) {
    const Eigen::VectorXd rounded = quarter_rounded(k, closed, chi, o.min_cone_angle);
    std::vector<int> kept;
    std::vector<double> kept_k;
    for (int i = 0; i < rounded.size(); ++i) {
      if (rounded[i] != 0) kept.push_back(cones[i]), kept_k.push_back(rounded[i]);
    }
    cones = kept;
    k = Eigen::Map<Eigen::VectorXd>(kept_k.data(), static_cast<long>(kept_k.size()));
    search.move_quarters(cones, k, budget);
    u = model.prescribed(cones, k);
  }
  // A cone of no curvature is none (a torus's one cone at a budget of one: Gauss-Bonnet leaves it
  // flat); u is the same without it.
  for (size_t i = 0; i < cones.size(); ++i) {
    if (std::abs(k[static_cast<long>(i)]) > 1e-9)
      result.cones.push_back({cones[i], 2 * kPi - k[i]});
  }
  result.u = u.size() ? u : Eigen::VectorXd::Zero(mesh.num_vertices());
  result.distortion = area_weighted_deviation(model.area(), result.u);
  result.sharp_cone = state.solution.ok && !search.angles_ok(cones, k);
  // With quarter turns, the rounded cones' D decides.
  result.bound_reached = o.quarter_angles ? state.solution.ok && !result.sharp_cone &&
                                                result.distortion <= o.distortion_bound
                                          : search.done(state);
  if (!result.bound_reached) {
    // The greedy stops at the budget, or where no vertex is left for a cone (a small part).
    const std::string stopped =
        static_cast<int>(state.cones.size()) < budget
            ? "with no vertex left for another cone"
            : "at the budget of " + std::to_string(budget) + (budget == 1 ? " cone" : " cones");
    const std::string d =
        "the linear model's D " +
        std::string(o.quarter_angles ? "with the cone angles in quarter turns " : "") + "is " +
        std::to_string(result.distortion);
    if (!state.solution.ok) {
      result.why_not =
          "no cone set of at most " + std::to_string(budget) + " cones gives a flat metric";
    } else if (result.sharp_cone) {
      result.why_not = "a cone sharper than the floor remains " + stopped + " (" + d + ")";
    } else if (o.quarter_angles && search.done(state)) {
      result.why_not = d;  // the bound was reached before the rounding
    } else {
      result.why_not = d + " " + stopped;
    }
  }
  const double mean = model.area().dot(result.u);
  result.max_deviation = (result.u.array() - mean).abs().maxCoeff();
  result.factorizations = model.factored() ? 1 : 0;
  result.back_solves = model.back_solves() + (model.factored() ? 1 : 0);
  result.seconds = detail::seconds_since(started);
  return result;
}

}  // namespace ricci
