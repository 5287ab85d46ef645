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

std::vector<int> cone_set_step(std::vector<int> cones, int v, int moved) {
  if (v < 0) {
    cones.erase(cones.begin() + moved);
  } else if (moved >= 0) {
    cones[static_cast<size_t>(moved)] = v;
  } else {
    cones.push_back(v);
  }
  return cones;
}

namespace {

// The indices 0 .. size - 1 but i.
std::vector<int> all_but(int size, int i) {
  std::vector<int> keep;
  keep.reserve(static_cast<size_t>(size));
  for (int j = 0; j < size; ++j) {
    if (j != i) keep.push_back(j);
  }
  return keep;
}

// x without its entry i.
Eigen::VectorXd without_entry(const Eigen::VectorXd& x, int i) {
  Eigen::VectorXd out(x.size() - 1);
  out << x.head(i), x.tail(x.size() - 1 - i);
  return out;
}

// x with a 0 inserted before its entry i.
Eigen::VectorXd zero_inserted(const Eigen::VectorXd& x, int i) {
  Eigen::VectorXd out(x.size() + 1);
  out << x.head(i), 0, x.tail(x.size() - i);
  return out;
}

// A pivot s of a Schur step whose other terms are d and d - s vanishes, relative to them, where
// the larger system is singular.
bool pivot_ok(double s, double d) {
  return std::abs(s) > kSingular * (std::abs(d) + std::abs(d - s));
}

}  // namespace

bool HeldSystem::reset(const std::vector<int>& cones) {
  cones_ = cones;
  updates_ = 0;
  valid_ = false;
  if (cones.empty()) return false;
  const auto [a, rhs] = model_.system(cones);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
  ++factorizations_;
  if (!(lu.rcond() > kSingular)) return false;  // as LinearConeModel::held
  inverse_ = lu.inverse();
  x_ = lu.solve(rhs);
  valid_ = x_.allFinite();
  if (valid_) reset_sums();
  return valid_;
}

void HeldSystem::reset_sums() {
  const long m = static_cast<long>(cones_.size());
  gram_.resize(m, m);
  sum_.resize(m);
  with_g_.resize(m);
  for (long j = 0; j < m; ++j) {
    const int c = cones_[static_cast<size_t>(j)];
    gram_.col(j) = model_.gram_with(c, cones_).head(m);
    sum_[j] = model_.column_sum(c);
    with_g_[j] = model_.column_with_g(c);
  }
}

LinearConeModel::Solution HeldSystem::solution() const {
  if (!valid_) return {};
  const long m = static_cast<long>(cones_.size());
  return step_solution(m, x_, x_.head(m), -1, 0);
}

bool refine_held_solution(const Eigen::MatrixXd& a, const Eigen::VectorXd& rhs,
                          const Eigen::MatrixXd& inverse, Eigen::VectorXd& x, double bound) {
  const double scale =
      a.cwiseAbs().rowwise().sum().maxCoeff() * x.cwiseAbs().maxCoeff() + rhs.cwiseAbs().maxCoeff();
  const Eigen::VectorXd residual = rhs - a * x;
  if (!(residual.cwiseAbs().maxCoeff() <= bound * scale)) return false;
  Eigen::VectorXd refined = x;
  refined += inverse * residual;  // accumulated onto x, rounded as an update in place
  if (!refined.allFinite()) return false;
  x = refined;
  return true;
}

bool HeldSystem::drifted() {
  const auto [a, rhs] = model_.system(cones_);
  return !refine_held_solution(a, rhs, inverse_, x_, drift_);
}

bool HeldSystem::due_for_factorization() {
  if (++updates_ <= kStepsBetweenDriftChecks) return false;
  updates_ = 0;
  return drifted();
}

LinearConeModel::Solution HeldSystem::step_solution(long cones, const Eigen::VectorXd& x,
                                                    const Eigen::VectorXd& k_held, int v,
                                                    double k_v) const {
  LinearConeModel::Solution s;
  if (!x.allFinite()) return s;
  const long m = cones;
  s.k = x.head(m);
  s.c = model_.closed() ? x[m] : 0;
  double quadratic = k_held.dot(gram_ * k_held);
  double with_g = k_held.dot(with_g_), sum = k_held.dot(sum_);
  if (v >= 0) {
    const Eigen::VectorXd row = model_.gram_with(v, cones_);
    const long held = static_cast<long>(cones_.size());
    quadratic += k_v * (2 * row.head(held).dot(k_held) + k_v * row[held]);
    with_g += k_v * model_.column_with_g(v);
    sum += k_v * model_.column_sum(v);
  }
  s.d = model_.distortion(quadratic, with_g, sum);
  s.ok = true;
  return s;
}

bool HeldSystem::droppable(int i) const {
  // Without cone i the system's pivot there is 1 / P(i, i), against its entry R(e_c)[c].
  const double p = inverse_(i, i);
  return valid_ && p != 0 && pivot_ok(1 / p, model_.entry(cones_[i], cones_[i]));
}

// Of the inverse P of a system, the inverse of the system without index i is P's block without i
// less P(., i) P(i, .) / P(i, i), and its solution x less P(., i) x_i / P(i, i).
Eigen::VectorXd HeldSystem::x_without(int i) const {
  return without_entry(x_, i) - without_entry(inverse_.col(i), i) * (x_[i] / inverse_(i, i));
}

void HeldSystem::drop_index(int i) {
  const std::vector<int> keep = all_but(static_cast<int>(x_.size()), i);
  const Eigen::VectorXd column = inverse_(keep, i);
  const Eigen::RowVectorXd row = inverse_(i, keep);
  const Eigen::MatrixXd rest = inverse_(keep, keep) - column * row / inverse_(i, i);
  x_ = x_without(i);
  inverse_ = rest;
}

LinearConeModel::Solution HeldSystem::without(int i) const {
  if (!droppable(i)) return {};
  const Eigen::VectorXd x = x_without(i);
  // k at the set's indices, 0 at the cone left out.
  const long m = static_cast<long>(cones_.size());
  return step_solution(m - 1, x, zero_inserted(x.head(m - 1), i), -1, 0);
}

HeldSystem::Border HeldSystem::border(const std::vector<int>& base, int v) {
  model_.solve_columns({v});
  const int mb = static_cast<int>(base.size());
  const int rb = mb + (model_.closed() ? 1 : 0);
  Border b;
  b.a = Eigen::VectorXd::Ones(rb);  // the constant's entries stay 1
  b.r = Eigen::RowVectorXd::Ones(rb);
  for (int j = 0; j < mb; ++j) b.a[j] = model_.entry(base[j], v), b.r[j] = model_.entry(v, base[j]);
  b.d = model_.entry(v, v);
  return b;
}

HeldSystem::Grown HeldSystem::grow(const Eigen::VectorXd& x, const Eigen::VectorXd& ba,
                                   const Border& b, const std::vector<int>& base, int v, int at) {
  // The system A (inverse B, solution x) bordered by v's row r, column a and corner d, its
  // right-hand side b_v: the solution is (x - B a y, y), y = (b_v - r.x) / s, s = d - r.B a.
  const int rb = static_cast<int>(x.size());
  Grown g;
  g.r = b.r;
  g.ba = ba;
  g.s = b.d - g.r.dot(g.ba);
  if (!pivot_ok(g.s, b.d)) return g;
  const double y = (-model_.g()[v] - g.r.dot(x)) / g.s;
  if (!std::isfinite(y)) return g;
  // The grown solution, v's entry moved to index `at` among the cones (the constant last).
  const Eigen::VectorXd rest = x - g.ba * y;
  g.order.clear();  // grown index -> the bordered system's (rest, then v)
  for (int j = 0; j <= rb; ++j) g.order.push_back(j < at ? j : j == at ? rb : j - 1);
  Eigen::VectorXd bordered(rb + 1);
  bordered << rest, y;
  g.x = bordered(g.order);
  g.cones = base;
  g.cones.insert(g.cones.begin() + at, v);
  g.ok = true;
  return g;
}

LinearConeModel::Solution HeldSystem::with(int v, int moved) {
  if (!valid_ || (moved >= 0 && !droppable(moved))) return {};
  const long m = static_cast<long>(cones_.size());
  if (moved < 0) {
    const Border b = border(cones_, v);
    const Grown g = grow(x_, inverse_ * b.a, b, cones_, v, static_cast<int>(m));
    if (!g.ok) return {};
    return step_solution(m + 1, g.x, g.x.head(m), v, g.x[m]);
  }
  // Moved: the set without cone i (its inverse B = P's block without i less P(., i) P(i, .) /
  // P(i, i), not formed) bordered by v. B a is P a' (a with 0 at i) without i, less P(., i)
  // (P a')_i / P(i, i).
  const int i = moved;
  const std::vector<int> base = cone_set_step(cones_, -1, i);
  const Border b = border(base, v);
  const Eigen::VectorXd pa = inverse_ * zero_inserted(b.a, i);
  const double pivot = inverse_(i, i);
  const Eigen::VectorXd column = without_entry(inverse_.col(i), i);
  const Eigen::VectorXd ba = without_entry(pa, i) - column * (pa[i] / pivot);
  const Grown g = grow(x_without(i), ba, b, base, v, i);
  if (!g.ok) return {};
  // v took cone i's index: k at the set's indices, 0 at i, and v's.
  Eigen::VectorXd k_held = g.x.head(m);
  const double k_v = k_held[i];
  k_held[i] = 0;
  return step_solution(m, g.x, k_held, v, k_v);
}

void HeldSystem::remove(int i) {
  if (!droppable(i) || due_for_factorization()) {
    reset(cone_set_step(cones_, -1, i));
    return;
  }
  drop_index(i);
  cones_.erase(cones_.begin() + i);
  const std::vector<int> keep = all_but(static_cast<int>(cones_.size()) + 1, i);
  gram_ = Eigen::MatrixXd(gram_(keep, keep));
  sum_ = Eigen::VectorXd(sum_(keep));
  with_g_ = Eigen::VectorXd(with_g_(keep));
}

void HeldSystem::add(int v, int moved) {
  const std::vector<int> after = cone_set_step(cones_, v, moved);
  if (!valid_ || due_for_factorization() || (moved >= 0 && !droppable(moved))) {
    reset(after);
    return;
  }
  std::vector<int> base = cones_;
  if (moved >= 0) {
    drop_index(moved);
    base.erase(base.begin() + moved);
  }
  const Border b = border(base, v);
  const Grown g =
      grow(x_, inverse_ * b.a, b, base, v, moved >= 0 ? moved : static_cast<int>(base.size()));
  if (!g.ok) {
    reset(after);
    return;
  }
  // The bordered inverse [B + B a r B / s, -B a / s; -r B / s, 1 / s], in the grown order.
  const long rb = x_.size();
  const Eigen::RowVectorXd rb_row = g.r * inverse_;
  Eigen::MatrixXd bordered(rb + 1, rb + 1);
  bordered.topLeftCorner(rb, rb) = inverse_ + g.ba * rb_row / g.s;
  bordered.topRightCorner(rb, 1) = -g.ba / g.s;
  bordered.bottomLeftCorner(1, rb) = -rb_row / g.s;
  bordered(rb, rb) = 1 / g.s;
  inverse_ = bordered(g.order, g.order);
  x_ = g.x;
  // v's sums in its place: the row of cone i replaced, or one more row.
  const Eigen::VectorXd row = model_.gram_with(v, cones_);
  const long m = static_cast<long>(cones_.size());
  const long at = moved >= 0 ? moved : m;
  if (moved < 0) {
    gram_.conservativeResize(m + 1, m + 1);
    sum_.conservativeResize(m + 1);
    with_g_.conservativeResize(m + 1);
  }
  cones_ = g.cones;
  gram_.row(at).head(m) = row.head(m).transpose();
  gram_.col(at).head(m) = row.head(m);
  gram_(at, at) = row[m];
  sum_[at] = model_.column_sum(v);
  with_g_[at] = model_.column_with_g(v);
}

}  // namespace ricci
