#include "ricci/flow/cone_placement.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <unordered_map>

#include <Eigen/Dense>

#include "flow/delaunay.h"
#include "flow/hessian.h"
#include "flow/metric.h"
#include "ricci/mesh/errors.h"

namespace ricci {

namespace {

// Per vertex: a third of the areas of its input faces, summing to 1.
Eigen::VectorXd vertex_areas(const CompactMesh& mesh) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(mesh.num_vertices());
  const auto& p = mesh.positions();
  for (const auto& t : mesh.faces()) {
    const double a = 0.5 * (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).norm();
    for (int v : t) area[v] += a / 3;
  }
  return area / area.sum();
}

double distortion_of(const Eigen::VectorXd& area, const Eigen::VectorXd& u) {
  const double mean = area.dot(u);
  return std::sqrt(area.dot((u.array() - mean).square().matrix()));
}

// The linear model on the input metric's intrinsic Delaunay triangulation: H factored once over
// the free vertices (the interior ones; on a closed surface all but one, pinned), K0, and R(e_v)
// per vertex on request.
class LinearConeModel {
 public:
  LinearConeModel(const CompactMesh& mesh, LinearSolverKind kind)
      : mesh_(mesh), delaunay_(mesh), solver_(kind) {
    ConformalStructure structure = initialize_scheme(mesh, Geometry::Euclidean, SchemeOptions());
    make_input_delaunay(delaunay_, structure);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(mesh.num_vertices());
    const MetricState state = evaluate_metric(delaunay_, structure, zero);
    k0_ = curvature(delaunay_, state);
    free_index_.assign(mesh.num_vertices(), -1);
    int n = 0;
    const int pinned = mesh.is_closed() ? 0 : -1;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (v != pinned && !mesh.is_boundary_vertex(v)) free_index_[v] = n++;
    }
    g_ = Eigen::VectorXd::Zero(mesh.num_vertices());
    if (n == 0) return;  // every vertex on the boundary: u = 0 is the only flat metric here
    HessianAssembler assembler(delaunay_, free_index_);
    const SparseMatrix& h = assembler.assemble(state);
    solver_.analyze(h);
    factored_ = true;
    if (!solver_.factorize(h)) {
      throw SolverError(
          "cone placement: the cotangent Laplacian of the intrinsic Delaunay triangulation is not "
          "positive definite (degenerate input triangles?)");
    }
    Eigen::VectorXd b(n);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (free_index_[v] >= 0) b[free_index_[v]] = -k0_[v];
    }
    g_ = scatter(solver_.solve(b));
  }

  const Eigen::VectorXd& curvature0() const { return k0_; }
  const Eigen::VectorXd& cone_free() const { return g_; }
  int back_solves() const { return back_solves_; }
  bool factored() const { return factored_; }

  // R(e_v): 0 for a vertex without a row (pinned or on the boundary).
  const Eigen::VectorXd& column(int v) {
    auto found = columns_.find(v);
    if (found != columns_.end()) return found->second;
    Eigen::VectorXd b = Eigen::VectorXd::Zero(solver_rows());
    if (free_index_[v] >= 0) {
      b[free_index_[v]] = 1;
      ++back_solves_;
      return columns_.emplace(v, scatter(solver_.solve(b))).first->second;
    }
    return columns_.emplace(v, Eigen::VectorXd::Zero(mesh_.num_vertices())).first->second;
  }
  // Columns of vertices no longer tried are dropped (n doubles each).
  void keep_only(const std::vector<int>& vertices) {
    std::unordered_map<int, Eigen::VectorXd> kept;
    for (int v : vertices) {
      auto found = columns_.find(v);
      if (found != columns_.end()) kept.emplace(v, std::move(found->second));
    }
    columns_ = std::move(kept);
  }

  struct Solution {
    Eigen::VectorXd k;  // per cone
    Eigen::VectorXd u;  // per vertex
    bool ok = false;
  };
  // u = 0 at the cones: their curvatures k (and on a closed surface the constant c) from u_C = 0
  // and Gauss-Bonnet.
  Solution held(const std::vector<int>& cones) {
    const int m = static_cast<int>(cones.size());
    const bool closed = mesh_.is_closed();
    Solution s;
    if (closed && m == 0) {
      s.u = g_.array() - g_.mean();
      s.ok = mesh_.euler_characteristic() == 0;
      s.k.resize(0);
      return s;
    }
    if (m == 0) {  // u = 0 on the boundary: the free-boundary model itself
      s.u = g_;
      s.k.resize(0);
      s.ok = true;
      return s;
    }
    const int rows = m + (closed ? 1 : 0);
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, rows);
    Eigen::VectorXd rhs(rows);
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < m; ++j) a(i, j) = column(cones[j])[cones[i]];
      rhs[i] = -g_[cones[i]];
      if (closed) a(i, m) = 1;
    }
    if (closed) {
      a.row(m).head(m).setOnes();
      rhs[m] = 2 * kPi * mesh_.euler_characteristic();
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
    if (lu.rank() < rows) return s;
    const Eigen::VectorXd x = lu.solve(rhs);
    s.k = x.head(m);
    s.u = g_;
    for (int j = 0; j < m; ++j) s.u += s.k[j] * column(cones[j]);
    if (closed) s.u.array() += x[m];
    for (int c : cones) s.u[c] = 0;  // held there: exactly, not to round-off
    s.ok = s.u.allFinite();
    return s;
  }
  // The cones' curvatures given: u free at them (the mean 0 on a closed surface).
  Eigen::VectorXd prescribed(const std::vector<int>& cones, const Eigen::VectorXd& k) {
    Eigen::VectorXd u = g_;
    for (size_t j = 0; j < cones.size(); ++j) u += k[j] * column(cones[j]);
    if (mesh_.is_closed()) u.array() -= u.mean();
    return u;
  }

 private:
  int solver_rows() const {
    return static_cast<int>(
        std::count_if(free_index_.begin(), free_index_.end(), [](int i) { return i >= 0; }));
  }
  Eigen::VectorXd scatter(const Eigen::VectorXd& x) const {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(mesh_.num_vertices());
    for (int v = 0; v < mesh_.num_vertices(); ++v) {
      if (free_index_[v] >= 0) u[v] = x[free_index_[v]];
    }
    return u;
  }

  const CompactMesh& mesh_;
  IntrinsicTriangulation delaunay_;
  LinearSolver solver_;
  std::vector<int> free_index_;
  Eigen::VectorXd k0_, g_;
  std::unordered_map<int, Eigen::VectorXd> columns_;
  int back_solves_ = 0;
  bool factored_ = false;
};

// The placement's search: a cone set, its solution and D.
class Search {
 public:
  Search(const CompactMesh& mesh, const ConePlacementOptions& o)
      : mesh_(mesh), o_(o), model_(mesh, o.linear_solver), area_(vertex_areas(mesh)) {
    is_cone_.assign(mesh.num_vertices(), 0);
  }

  LinearConeModel& model() { return model_; }
  const Eigen::VectorXd& area() const { return area_; }

  struct State {
    std::vector<int> cones;
    LinearConeModel::Solution solution;
    double d = std::numeric_limits<double>::infinity();
    bool angles_ok = false;
  };
  State evaluate(std::vector<int> cones) {
    State s;
    s.cones = std::move(cones);
    s.solution = model_.held(s.cones);
    if (!s.solution.ok) return s;
    s.d = distortion_of(area_, s.solution.u);
    s.angles_ok = (s.solution.k.array() <= 2 * kPi - o_.min_cone_angle).all();
    return s;
  }
  bool done(const State& s) const { return s.solution.ok && s.angles_ok && s.d <= bound(); }
  double bound() const { return o_.distortion_bound; }

  // The interior vertex, not a cone, of largest |u| (|u - mean| without cones); -1 if none.
  int farthest(const State& s) {
    if (!s.solution.ok) return -1;
    mark(s.cones);
    const Eigen::VectorXd& u = s.solution.u;
    const double mean = s.cones.empty() ? area_.dot(u) : 0;
    int best = -1;
    double largest = -1;
    for (int v = 0; v < mesh_.num_vertices(); ++v) {
      if (is_cone_[v] || mesh_.is_boundary_vertex(v)) continue;
      const double d = std::abs(u[v] - mean);
      if (d > largest) largest = d, best = v;
    }
    unmark(s.cones);
    return best;
  }

  // Near the sharpest cone (two rings), the vertex whose cone leaves the sharpest angle widest.
  int widen_sharpest(const State& s) {
    int sharpest = 0;
    s.solution.k.maxCoeff(&sharpest);
    mark(s.cones);
    std::vector<int> ring = rings(s.cones[sharpest], 2);
    int best = -1;
    double widest = -std::numeric_limits<double>::infinity();
    for (int v : ring) {
      if (is_cone_[v] || mesh_.is_boundary_vertex(v)) continue;
      std::vector<int> tried = s.cones;
      tried.push_back(v);
      const State t = evaluate(tried);
      if (!t.solution.ok) continue;
      const double angle = 2 * kPi - t.solution.k.maxCoeff();
      if (angle > widest) widest = angle, best = v;
    }
    unmark(s.cones);
    return best;
  }

 private:
  void mark(const std::vector<int>& cones) {
    for (int c : cones) is_cone_[c] = 1;
  }
  void unmark(const std::vector<int>& cones) {
    for (int c : cones) is_cone_[c] = 0;
  }
  std::vector<int> rings(int from, int depth) const {
    if (adjacent_.empty()) {
      adjacent_.resize(mesh_.num_vertices());
      for (int e = 0; e < mesh_.num_edges(); ++e) {
        const auto [a, b] = mesh_.edge_vertices(e);
        adjacent_[a].push_back(b), adjacent_[b].push_back(a);
      }
    }
    std::vector<int> found{from}, frontier{from};
    for (int d = 0; d < depth; ++d) {
      std::vector<int> next;
      for (int v : frontier) {
        for (int w : adjacent_[v]) {
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
  Eigen::VectorXd area_;
  std::vector<char> is_cone_;
  mutable std::vector<std::vector<int>> adjacent_;
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
  return distortion_of(vertex_areas(mesh), u);
}

ConePlacement place_cones(const CompactMesh& mesh, const ConePlacementOptions& o) {
  if (!(o.distortion_bound > 0) || o.max_cones < 0 || !(o.min_cone_angle > 0) ||
      !(o.min_cone_angle < 2 * kPi) || o.relocation_sweeps < 0) {
    throw InvalidArgumentError(
        "cone placement: the distortion bound and the cone floor must be positive (the floor "
        "below 2 pi), the budget and the sweeps non-negative");
  }
  const auto started = std::chrono::steady_clock::now();
  const int budget = o.max_cones > 0 ? o.max_cones : kDefaultConeBudget;
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
    if (v < 0) v = search.farthest(state);
    if (v < 0) break;
    std::vector<int> more = state.cones;
    more.push_back(v);
    state = search.evaluate(more);
    model.keep_only(state.cones);  // the candidates' columns tried and left (n doubles each)
  }

  // === Gauss-Seidel: each cone moved to the farthest vertex of the set without it.
  for (int sweep = 0; sweep < o.relocation_sweeps && !state.cones.empty(); ++sweep) {
    int moved = 0;
    for (size_t i = 0; i < state.cones.size(); ++i) {
      std::vector<int> without = state.cones;
      without.erase(without.begin() + static_cast<long>(i));
      const Search::State rest = search.evaluate(without);
      if (!rest.solution.ok) continue;
      const int v = search.farthest(rest);
      if (v < 0 || v == state.cones[i]) continue;
      std::vector<int> there = state.cones;
      there[i] = v;
      const Search::State trial = search.evaluate(there);
      const bool better = trial.solution.ok && (trial.angles_ok || !state.angles_ok) &&
                          trial.d < state.d * (1 - 1e-9);
      if (better) state = trial, ++moved;
    }
    result.relocations += moved;
    model.keep_only(state.cones);
    if (moved == 0) break;
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
      std::vector<int> without;
      for (int v : state.cones) {
        if (v != c) without.push_back(v);
      }
      const Search::State trial = search.evaluate(without);
      if (search.done(trial)) state = trial, ++result.dropped;
    }
  }

  result.bound_reached = search.done(state);
  if (!result.bound_reached) {
    if (!state.solution.ok) {
      result.why_not =
          "no cone set of at most " + std::to_string(budget) + " cones gives a flat metric";
    } else if (!state.angles_ok) {
      result.why_not = "a cone sharper than the floor remains at the budget of " +
                       std::to_string(budget) + " cones";
    } else {
      result.why_not = "the budget of " + std::to_string(budget) + " cones leaves D at " +
                       std::to_string(state.d);
    }
  }
  Eigen::VectorXd k = state.solution.k;
  Eigen::VectorXd u = state.solution.u;
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
    u = model.prescribed(cones, k);
  }
  for (size_t i = 0; i < cones.size(); ++i) result.cones.push_back({cones[i], 2 * kPi - k[i]});
  result.u = u.size() ? u : Eigen::VectorXd::Zero(mesh.num_vertices());
  result.distortion = distortion_of(search.area(), result.u);
  if (o.quarter_angles && result.bound_reached && result.distortion > o.distortion_bound) {
    result.bound_reached = false;
    result.why_not = "rounding the cone angles to quarter turns leaves D at " +
                     std::to_string(result.distortion);
  }
  const double mean = search.area().dot(result.u);
  result.max_deviation = (result.u.array() - mean).abs().maxCoeff();
  result.factorizations = model.factored() ? 1 : 0;
  result.back_solves = model.back_solves() + (model.factored() ? 1 : 0);
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace ricci
