#include "flow/linear_cone_model.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "flow/hessian.h"
#include "flow/metric.h"
#include "ricci/mesh/errors.h"

namespace ricci {

Eigen::VectorXd normalized_vertex_areas(const CompactMesh& mesh) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(mesh.num_vertices());
  const auto& p = mesh.positions();
  for (const auto& t : mesh.faces()) {
    const double a = 0.5 * (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).norm();
    for (int v : t) area[v] += a / 3;
  }
  return area / area.sum();
}

double area_weighted_deviation(const Eigen::VectorXd& area, const Eigen::VectorXd& u) {
  const double mean = area.dot(u);
  return std::sqrt(area.dot((u.array() - mean).square().matrix()));
}

LinearConeModel::LinearConeModel(const CompactMesh& mesh, LinearSolverKind kind,
                                 size_t by_solve_from, long weighed_columns)
    : mesh_(mesh), delaunay_(mesh), solver_(kind), area_(normalized_vertex_areas(mesh)) {
  ConformalStructure structure = initialize_scheme(mesh, Geometry::Euclidean, SchemeOptions());
  make_input_delaunay(delaunay_, structure);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(mesh.num_vertices());
  const MetricState state = evaluate_metric(delaunay_, structure, zero);
  k0_ = curvature(delaunay_, state);
  free_index_.assign(mesh.num_vertices(), -1);
  const int pinned = mesh.is_closed() ? 0 : -1;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (v != pinned && !mesh.is_boundary_vertex(v)) free_index_[v] = rows_++;
  }
  slot_of_.assign(mesh.num_vertices(), -1);
  g_ = Eigen::VectorXd::Zero(mesh.num_vertices());
  if (rows_ > 0) {  // else every vertex is on the boundary: u = 0 is the only flat metric here
    HessianAssembler assembler(delaunay_, free_index_);
    const SparseMatrix& h = assembler.assemble(state);
    solver_.analyze(h);
    factored_ = true;
    if (!solver_.factorize(h)) {
      throw SolverError(
          "cone placement: the cotangent Laplacian of the intrinsic Delaunay triangulation is not "
          "positive definite (degenerate input triangles?)");
    }
    Eigen::VectorXd b(rows_);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (free_index_[v] >= 0) b[free_index_[v]] = -k0_[v];
    }
    g_ = scatter(solver_.solve(b));
    by_solve_from_ =
        by_solve_from > 0
            ? by_solve_from
            : static_cast<size_t>(std::ceil(
                  std::max(kSolveOverPass * static_cast<double>(solver_.factor_entries()) / rows_,
                           kCachedColumns / (8.0 * mesh.num_vertices()))));
  }
  max_weighed_ = weighed_columns > 0
                     ? weighed_columns
                     : static_cast<long>(
                           std::max(1.0, kWeighedBytes / (8.0 * std::max(1, mesh.num_vertices()))));
  g_sum_ = area_.dot(g_);
  g_square_ = area_.dot(g_.cwiseProduct(g_));
}

Eigen::VectorXd LinearConeModel::scatter(const Eigen::VectorXd& x) const {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(mesh_.num_vertices());
  for (int v = 0; v < mesh_.num_vertices(); ++v) {
    if (free_index_[v] >= 0) u[v] = x[free_index_[v]];
  }
  return u;
}

int LinearConeModel::store(int v, const Eigen::VectorXd& column) {
  int s = 0;
  if (!free_slots_.empty()) {
    s = free_slots_.back();
    free_slots_.pop_back();
  } else {
    s = static_cast<int>(vertex_of_slot_.size());
    vertex_of_slot_.push_back(-1);
    row_seen_.push_back(0);
    weighed_of_slot_.push_back(-1);
    passes_.push_back(0);
    if (s >= columns_.cols()) {  // room doubles: columns are appended one by one
      const int room = std::max(8, 2 * static_cast<int>(columns_.cols()));
      columns_.conservativeResize(mesh_.num_vertices(), room);
      gram_.conservativeResize(room, room);
      sum_.conservativeResize(room);
      with_g_.conservativeResize(room);
    }
  }
  columns_.col(s) = column;
  row_seen_[s] = 0;
  forget_weighed(s);
  vertex_of_slot_[s] = v;
  slot_of_[v] = s;
  const Eigen::VectorXd weighted = area_.cwiseProduct(column);
  // Its products with the other columns when a set first pairs them (gram): a search pairs a
  // column with the few cones it is tried beside, not with every column kept. Stale slots too: a
  // stale entry is rewritten when its slot is reused.
  const int used = static_cast<int>(vertex_of_slot_.size());
  gram_.block(s, 0, 1, used).setConstant(kNotYet);
  gram_.block(0, s, used, 1).setConstant(kNotYet);
  sum_[s] = weighted.sum();
  with_g_[s] = weighted.dot(g_);
  return s;
}

double LinearConeModel::gram(int a, int b) const {
  double& entry = gram_(a, b);
  if (std::isnan(entry)) {
    const int wa = weighed_of_slot_[a], wb = weighed_of_slot_[b];
    if (wa >= 0) {
      entry = weighed_(vertex_of_slot_[b], wa);
    } else if (wb >= 0) {
      entry = weighed_(vertex_of_slot_[a], wb);
    } else {
      // In one order whichever pair is asked first: the same rounding for (a, b) and (b, a).
      const int first = std::min(a, b), second = std::max(a, b);
      entry = (columns_.col(first).array() * area_.array() * columns_.col(second).array()).sum();
      // A column summed with this many others has cost what R(A col) costs: that is solved, and
      // its sums with any column are then read from it, where there is room to keep it (else
      // each later sum would solve it again).
      for (int c : {a, b}) {
        if (++passes_[c] >= by_solve_from_ && weighed_of_slot_[c] < 0 && room_to_weigh()) {
          gram_row(c);
        }
        if (a == b) break;
      }
    }
    gram_(b, a) = entry;
  }
  return entry;
}

void LinearConeModel::gram_row(int a) const {
  Eigen::VectorXd b(rows_);
  for (int v = 0; v < mesh_.num_vertices(); ++v) {
    if (free_index_[v] >= 0) b[free_index_[v]] = area_[v] * columns_(v, a);
  }
  const Eigen::VectorXd x = scatter(solver_.solve_sparse(b.sparseView()).col(0));
  ++back_solves_;
  for (size_t s = 0; s < vertex_of_slot_.size(); ++s) {
    const int v = vertex_of_slot_[s];
    if (v < 0) continue;
    gram_(a, static_cast<long>(s)) = gram_(static_cast<long>(s), a) = x[v];
  }
  if (free_weighed_.empty() && weighed_.cols() < max_weighed_) {
    const long room = std::min<long>(max_weighed_, std::max<long>(8, 2 * weighed_.cols()));
    for (long w = room - 1; w >= weighed_.cols(); --w) free_weighed_.push_back(static_cast<int>(w));
    weighed_.conservativeResize(mesh_.num_vertices(), room);
  }
  if (weighed_of_slot_[a] < 0 && !free_weighed_.empty()) {
    weighed_of_slot_[a] = free_weighed_.back();
    free_weighed_.pop_back();
  }
  if (weighed_of_slot_[a] >= 0) weighed_.col(weighed_of_slot_[a]) = x;
}

bool LinearConeModel::room_to_weigh() const {
  return !free_weighed_.empty() || weighed_.cols() < max_weighed_;
}

void LinearConeModel::forget_weighed(int s) {
  if (weighed_of_slot_[s] >= 0) free_weighed_.push_back(weighed_of_slot_[s]);
  weighed_of_slot_[s] = -1;
  passes_[s] = 0;
}

void LinearConeModel::solve_columns(const std::vector<int>& vertices) {
  std::vector<int> missing;
  for (int v : vertices) {
    if (slot_of_[v] < 0 && std::find(missing.begin(), missing.end(), v) == missing.end()) {
      missing.push_back(v);
    }
  }
  std::vector<int> solved;
  for (int v : missing) {
    if (free_index_[v] >= 0) {
      solved.push_back(v);
    } else {
      store(v, Eigen::VectorXd::Zero(mesh_.num_vertices()));
    }
  }
  if (solved.empty()) return;
  std::vector<Eigen::Triplet<double>> units;
  for (size_t j = 0; j < solved.size(); ++j) {
    units.emplace_back(free_index_[solved[j]], static_cast<int>(j), 1.0);
  }
  SparseMatrix b(rows_, static_cast<long>(solved.size()));
  b.setFromTriplets(units.begin(), units.end());
  const Eigen::MatrixXd x = solver_.solve_sparse(b);
  back_solves_ += static_cast<int>(solved.size());
  for (size_t j = 0; j < solved.size(); ++j) store(solved[j], scatter(x.col(static_cast<long>(j))));
}

void LinearConeModel::keep_only(const std::vector<int>& vertices) {
  std::vector<char> kept(mesh_.num_vertices(), 0);
  for (int v : vertices) kept[v] = 1;
  for (size_t s = 0; s < vertex_of_slot_.size(); ++s) {
    const int v = vertex_of_slot_[s];
    if (v >= 0 && !kept[v]) {
      slot_of_[v] = -1;
      vertex_of_slot_[s] = -1;
      free_slots_.push_back(static_cast<int>(s));
      forget_weighed(static_cast<int>(s));
    }
  }
}

// D^2 = var(g) + 2 sum_j k_j cov(col_j, g) + sum_ij k_i k_j cov(col_i, col_j), the area-weighted
// (co)variances: the constant c drops out.
double LinearConeModel::distortion(const std::vector<int>& cones, const Eigen::VectorXd& k) const {
  const size_t m = cones.size();
  std::vector<int> slot(m);
  double with_g = 0, sum = 0;
  for (size_t i = 0; i < m; ++i) {
    slot[i] = slot_of_[cones[i]];
    with_g += k[static_cast<long>(i)] * with_g_[slot[i]];
    sum += k[static_cast<long>(i)] * sum_[slot[i]];
  }
  for (size_t i = 0; i < m; ++i) pair(slot[i], slot);
  double quadratic = 0;
  for (size_t j = 0; j < m; ++j) {
    double dot = 0;
    for (size_t i = 0; i < m; ++i) dot += k[static_cast<long>(i)] * gram(slot[i], slot[j]);
    quadratic += k[static_cast<long>(j)] * dot;
  }
  return distortion(quadratic, with_g, sum);
}

double LinearConeModel::distortion(double quadratic, double with_g, double sum) const {
  const double d2 =
      g_square_ - g_sum_ * g_sum_ + 2 * (with_g - sum * g_sum_) + quadratic - sum * sum;
  return std::sqrt(std::max(0.0, d2));
}

std::pair<Eigen::MatrixXd, Eigen::VectorXd> LinearConeModel::distortion_form(
    const std::vector<int>& cones) const {
  const long m = static_cast<long>(cones.size());
  std::vector<int> slot(cones.size());
  Eigen::VectorXd sum(m), b(m);
  for (long i = 0; i < m; ++i) {
    slot[static_cast<size_t>(i)] = slot_of_[cones[static_cast<size_t>(i)]];
    sum[i] = sum_[slot[static_cast<size_t>(i)]];
    b[i] = with_g_[slot[static_cast<size_t>(i)]] - sum[i] * g_sum_;
  }
  for (int a : slot) pair(a, slot);
  Eigen::MatrixXd q(m, m);
  for (long j = 0; j < m; ++j) {
    for (long i = 0; i < m; ++i) {
      q(i, j) = gram(slot[static_cast<size_t>(i)], slot[static_cast<size_t>(j)]) - sum[i] * sum[j];
    }
  }
  return {q, b};
}

void LinearConeModel::pair(int a, const std::vector<int>& slots) const {
  // A column paired with many of the set for the first time: its sums with every column at once,
  // R(A col) read at their vertices (sum A col_a col_b = e_b^T R(A col_a), H symmetric).
  // Each column is looked at once, when a set first holds it.
  if (row_seen_[a]) return;
  row_seen_[a] = 1;
  if (weighed_of_slot_[a] >= 0) return;  // its R(A col) kept: every sum a read
  size_t missing = 0;
  for (int b : slots) missing += std::isnan(gram_(a, b)) && weighed_of_slot_[b] < 0;
  if (missing >= by_solve_from_) gram_row(a);
}

Eigen::VectorXd LinearConeModel::gram_with(int v, const std::vector<int>& cones) const {
  std::vector<int> slots(cones.size());
  for (size_t j = 0; j < cones.size(); ++j) slots[j] = slot_of_[cones[j]];
  const int a = slot_of_[v];
  pair(a, slots);
  Eigen::VectorXd row(static_cast<long>(cones.size()) + 1);
  for (size_t j = 0; j < slots.size(); ++j) row[static_cast<long>(j)] = gram(a, slots[j]);
  row[static_cast<long>(slots.size())] = gram(a, a);
  return row;
}

LinearConeModel::Solution LinearConeModel::held(const std::vector<int>& cones) {
  Solution s;
  if (cones.empty()) {
    // Closed: a flat metric without cones only on a torus; with boundary, the free-boundary
    // model itself.
    s.ok = !mesh_.is_closed() || mesh_.euler_characteristic() == 0;
    s.d = distortion(cones, s.k);
    return s;
  }
  const auto [a, rhs] = system(cones);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
  // A singular system (no flat metric with u = 0 at these cones) shows as a vanishing reciprocal
  // condition number; the cones of a real search are far from it.
  if (!(lu.rcond() > kSingular)) return s;
  return solution(cones, lu.solve(rhs));
}

std::pair<Eigen::MatrixXd, Eigen::VectorXd> LinearConeModel::system(const std::vector<int>& cones) {
  solve_columns(cones);
  const int m = static_cast<int>(cones.size());
  const bool closed = mesh_.is_closed();
  const int rows = m + (closed ? 1 : 0);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, rows);
  Eigen::VectorXd rhs(rows);
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) a(i, j) = entry(cones[i], cones[j]);
    rhs[j] = -g_[cones[j]];
    if (closed) a(j, m) = a(m, j) = 1;
  }
  if (closed) rhs[m] = 2 * kPi * mesh_.euler_characteristic();
  return {a, rhs};
}

LinearConeModel::Solution LinearConeModel::solution(const std::vector<int>& cones,
                                                    const Eigen::VectorXd& x) const {
  Solution s;
  const long m = static_cast<long>(cones.size());
  if (!x.allFinite()) return s;
  s.k = x.head(m);
  s.c = mesh_.is_closed() ? x[m] : 0;
  s.d = distortion(cones, s.k);
  s.ok = true;
  return s;
}

Eigen::VectorXd LinearConeModel::combination(const std::vector<int>& cones,
                                             const Eigen::VectorXd& k) {
  solve_columns(cones);
  if (cones.size() >= by_solve_from_) {  // G k = R(sum_j k_j e_j): one back-solve
    ++back_solves_;
    return g_ + scatter(solver_.solve_sparse(curvatures({cones}, {&k})).col(0));
  }
  // Four columns a pass over u (u is read and written a quarter as often as column by column):
  // this sum is formed at every step of the greedy and of the sweeps, over all vertices.
  Eigen::VectorXd u = g_;
  const long n = u.size();
  double* out = u.data();
  const auto column = [&](size_t j) { return columns_.col(slot_of_[cones[j]]).data(); };
  size_t j = 0;
  for (; j + 4 <= cones.size(); j += 4) {
    const double *c0 = column(j), *c1 = column(j + 1), *c2 = column(j + 2), *c3 = column(j + 3);
    const double k0 = k[j], k1 = k[j + 1], k2 = k[j + 2], k3 = k[j + 3];
    for (long i = 0; i < n; ++i) out[i] += k0 * c0[i] + k1 * c1[i] + k2 * c2[i] + k3 * c3[i];
  }
  for (; j < cones.size(); ++j) u += k[j] * columns_.col(slot_of_[cones[j]]);
  return u;
}

SparseMatrix LinearConeModel::curvatures(const std::vector<std::vector<int>>& sets,
                                         const std::vector<const Eigen::VectorXd*>& k) const {
  std::vector<Eigen::Triplet<double>> entries;
  for (size_t s = 0; s < sets.size(); ++s) {
    for (size_t j = 0; j < sets[s].size(); ++j) {
      const int row = free_index_[sets[s][j]];
      if (row >= 0) entries.emplace_back(row, static_cast<int>(s), (*k[s])[static_cast<long>(j)]);
    }
  }
  SparseMatrix b(rows_, static_cast<long>(sets.size()));
  b.setFromTriplets(entries.begin(), entries.end());
  return b;
}

void LinearConeModel::held_at_cones(const std::vector<int>& cones, const Solution& s,
                                    Eigen::VectorXd& u) const {
  if (cones.empty() && mesh_.is_closed()) {
    u.array() -= u.mean();  // the torus: u up to a constant
  } else {
    u.array() += s.c;
  }
  for (int c : cones) u[c] = 0;  // held there: exactly, not to round-off
}

Eigen::VectorXd LinearConeModel::u(const std::vector<int>& cones, const Solution& s) {
  Eigen::VectorXd u = combination(cones, s.k);
  held_at_cones(cones, s, u);
  return u;
}

std::vector<Eigen::VectorXd> LinearConeModel::u(const std::vector<std::vector<int>>& sets,
                                                const std::vector<const Solution*>& solutions) {
  std::vector<const Eigen::VectorXd*> k;
  for (const Solution* s : solutions) k.push_back(&s->k);
  const Eigen::MatrixXd x = solver_.solve_sparse(curvatures(sets, k));
  back_solves_ += static_cast<int>(sets.size());
  std::vector<Eigen::VectorXd> us;
  for (size_t j = 0; j < sets.size(); ++j) {
    Eigen::VectorXd u = g_ + scatter(x.col(static_cast<long>(j)));
    held_at_cones(sets[j], *solutions[j], u);
    us.push_back(std::move(u));
  }
  return us;
}

Eigen::VectorXd LinearConeModel::prescribed(const std::vector<int>& cones,
                                            const Eigen::VectorXd& k) {
  Eigen::VectorXd u = combination(cones, k);
  if (mesh_.is_closed()) u.array() -= u.mean();
  return u;
}

}  // namespace ricci
