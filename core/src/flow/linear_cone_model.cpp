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

LinearConeModel::LinearConeModel(const CompactMesh& mesh, LinearSolverKind kind)
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
  }
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
    if (s >= columns_.cols()) {  // room doubles: columns are appended one by one
      const int room = std::max(8, 2 * static_cast<int>(columns_.cols()));
      columns_.conservativeResize(mesh_.num_vertices(), room);
      gram_.conservativeResize(room, room);
      sum_.conservativeResize(room);
      with_g_.conservativeResize(room);
    }
  }
  columns_.col(s) = column;
  vertex_of_slot_[s] = v;
  slot_of_[v] = s;
  const Eigen::VectorXd weighted = area_.cwiseProduct(column);
  const int used = static_cast<int>(vertex_of_slot_.size());
  // Against every slot in use, stale ones too: a stale entry is rewritten when its slot is reused.
  const Eigen::VectorXd row = columns_.leftCols(used).transpose() * weighted;
  gram_.block(s, 0, 1, used) = row.transpose();
  gram_.block(0, s, used, 1) = row;
  sum_[s] = weighted.sum();
  with_g_[s] = weighted.dot(g_);
  return s;
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
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(rows_, static_cast<long>(solved.size()));
  for (size_t j = 0; j < solved.size(); ++j) b(free_index_[solved[j]], static_cast<long>(j)) = 1;
  const Eigen::MatrixXd x = solver_.solve(b);
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
    }
  }
}

// D^2 = var(g) + 2 sum_j k_j cov(col_j, g) + sum_ij k_i k_j cov(col_i, col_j), the area-weighted
// (co)variances: the constant c drops out. The double sum reads the gram matrix a column at a
// time (it is called for every set a search tries).
double LinearConeModel::distortion(const std::vector<int>& cones, const Eigen::VectorXd& k) const {
  const size_t m = cones.size();
  std::vector<int> slot(m);
  double with_g = 0, sum = 0;
  for (size_t i = 0; i < m; ++i) {
    slot[i] = slot_of_[cones[i]];
    with_g += k[static_cast<long>(i)] * with_g_[slot[i]];
    sum += k[static_cast<long>(i)] * sum_[slot[i]];
  }
  double quadratic = 0;
  for (size_t j = 0; j < m; ++j) {
    const double* column = gram_.col(slot[j]).data();
    double dot = 0;
    for (size_t i = 0; i < m; ++i) dot += k[static_cast<long>(i)] * column[slot[i]];
    quadratic += k[static_cast<long>(j)] * dot;
  }
  const double d2 =
      g_square_ - g_sum_ * g_sum_ + 2 * (with_g - sum * g_sum_) + quadratic - sum * sum;
  return std::sqrt(std::max(0.0, d2));
}

LinearConeModel::Solution LinearConeModel::held(const std::vector<int>& cones) {
  const int m = static_cast<int>(cones.size());
  const bool closed = mesh_.is_closed();
  Solution s;
  s.k.resize(m);
  if (m == 0) {
    // Closed: a flat metric without cones only on a torus; with boundary, the free-boundary
    // model itself.
    s.ok = !closed || mesh_.euler_characteristic() == 0;
    s.d = distortion(cones, s.k);
    return s;
  }
  solve_columns(cones);
  const int rows = m + (closed ? 1 : 0);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, rows);
  Eigen::VectorXd rhs(rows);
  for (int j = 0; j < m; ++j) {
    const int sj = slot_of_[cones[j]];
    for (int i = 0; i < m; ++i) a(i, j) = columns_(cones[i], sj);
    rhs[j] = -g_[cones[j]];
    if (closed) a(j, m) = 1;
  }
  if (closed) {
    a.row(m).head(m).setOnes();
    rhs[m] = 2 * kPi * mesh_.euler_characteristic();
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
  // A singular system (no flat metric with u = 0 at these cones) shows as a vanishing reciprocal
  // condition number; the cones of a real search are far from it.
  if (!(lu.rcond() > 1e-12)) return s;
  const Eigen::VectorXd x = lu.solve(rhs);
  if (!x.allFinite()) return s;
  s.k = x.head(m);
  s.c = closed ? x[m] : 0;
  s.d = distortion(cones, s.k);
  s.ok = true;
  return s;
}

Eigen::VectorXd LinearConeModel::combination(const std::vector<int>& cones,
                                             const Eigen::VectorXd& k) {
  solve_columns(cones);
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

Eigen::VectorXd LinearConeModel::u(const std::vector<int>& cones, const Solution& s) {
  Eigen::VectorXd u = combination(cones, s.k);
  if (cones.empty() && mesh_.is_closed()) {
    u.array() -= u.mean();  // the torus: u up to a constant
  } else {
    u.array() += s.c;
  }
  for (int c : cones) u[c] = 0;  // held there: exactly, not to round-off
  return u;
}

Eigen::VectorXd LinearConeModel::prescribed(const std::vector<int>& cones,
                                            const Eigen::VectorXd& k) {
  Eigen::VectorXd u = combination(cones, k);
  if (mesh_.is_closed()) u.array() -= u.mean();
  return u;
}

}  // namespace ricci

namespace ricci {

namespace {

// Steps a held system takes between factorizations: each adds rounding of the order of its
// condition number times machine epsilon; a factorization costs about |C| steps.
constexpr int kStepsBetweenFactorizations = 32;

// Index order of a bordered system of m cones whose cone entries are `cones` positions, with c
// (closed) last.
std::vector<int> all_but(int size, int i) {
  std::vector<int> keep;
  keep.reserve(static_cast<size_t>(size));
  for (int j = 0; j < size; ++j) {
    if (j != i) keep.push_back(j);
  }
  return keep;
}

}  // namespace

Eigen::VectorXd HeldSystem::rhs(const std::vector<int>& cones) const {
  const int m = static_cast<int>(cones.size());
  Eigen::VectorXd b(m + (model_.closed() ? 1 : 0));
  for (int j = 0; j < m; ++j) b[j] = -model_.g()[cones[j]];
  if (model_.closed()) b[m] = 2 * kPi * model_.euler_characteristic();
  return b;
}

bool HeldSystem::reset(const std::vector<int>& cones) {
  cones_ = cones;
  updates_ = 0;
  valid_ = false;
  const int m = static_cast<int>(cones.size());
  if (m == 0) return false;
  model_.solve_columns(cones);
  const bool closed = model_.closed();
  const int rows = m + (closed ? 1 : 0);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, rows);
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) a(i, j) = model_.entry(cones[i], cones[j]);
    if (closed) a(j, m) = a(m, j) = 1;
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
  if (!(lu.rcond() > 1e-12)) return false;  // as LinearConeModel::held
  inverse_ = lu.inverse();
  x_ = lu.solve(rhs(cones));
  valid_ = x_.allFinite();
  return valid_;
}

LinearConeModel::Solution HeldSystem::solution_of(const std::vector<int>& cones,
                                                  const Eigen::VectorXd& x) const {
  LinearConeModel::Solution s;
  const long m = static_cast<long>(cones.size());
  if (!x.allFinite()) return s;
  s.k = x.head(m);
  s.c = model_.closed() ? x[m] : 0;
  s.d = model_.distortion(cones, s.k);
  s.ok = true;
  return s;
}

LinearConeModel::Solution HeldSystem::solution() const {
  if (!valid_) return {};
  return solution_of(cones_, x_);
}

void HeldSystem::drop_index(int i, Eigen::MatrixXd& inverse, Eigen::VectorXd& x) const {
  // Of the inverse P of a system, the inverse of the system without index i is P's block without
  // i less P(., i) P(i, .) / P(i, i), and its solution x less P(., i) x_i / P(i, i).
  const std::vector<int> keep = all_but(static_cast<int>(x.size()), i);
  const double pivot = inverse(i, i);
  const Eigen::VectorXd column = inverse(keep, i);
  const Eigen::RowVectorXd row = inverse(i, keep);
  const Eigen::MatrixXd rest = inverse(keep, keep) - column * row / pivot;
  const Eigen::VectorXd rest_x = x(keep) - column * (x[i] / pivot);
  inverse = rest;
  x = rest_x;
}

LinearConeModel::Solution HeldSystem::without(int i) const {
  if (!valid_ || !(std::abs(inverse_(i, i)) > 0)) return {};
  const std::vector<int> keep = all_but(static_cast<int>(x_.size()), i);
  const Eigen::VectorXd x = x_(keep) - inverse_(keep, i) * (x_[i] / inverse_(i, i));
  std::vector<int> cones = cones_;
  cones.erase(cones.begin() + i);
  return solution_of(cones, x);
}

namespace {

// A bordered step: the system A (inverse B, solution xb) with a row r, a column a and a corner d
// appended, its right-hand side b_v: the solution is (xb - B a y, y) with y = (b_v - r.xb) / s,
// s = d - r.B a; false where s vanishes (the larger system is singular).
struct Bordered {
  Eigen::VectorXd ba;  // B a
  double s = 0, y = 0;
  bool ok = false;
};

Bordered border(const Eigen::MatrixXd& b_inverse, const Eigen::VectorXd& xb,
                const Eigen::RowVectorXd& r, const Eigen::VectorXd& a, double d, double bv) {
  Bordered out;
  out.ba = b_inverse * a;
  const double rba = r.dot(out.ba);
  out.s = d - rba;
  if (!(std::abs(out.s) > 1e-12 * (std::abs(d) + std::abs(rba)))) return out;
  out.y = (bv - r.dot(xb)) / out.s;
  out.ok = std::isfinite(out.y);
  return out;
}

}  // namespace

LinearConeModel::Solution HeldSystem::with(int v, int moved) const {
  if (!valid_) return {};
  Eigen::MatrixXd b_inverse = inverse_;
  Eigen::VectorXd xb = x_;
  std::vector<int> base = cones_;
  if (moved >= 0) {
    if (!(std::abs(inverse_(moved, moved)) > 0)) return {};
    drop_index(moved, b_inverse, xb);
    base.erase(base.begin() + moved);
  }
  model_.solve_columns({v});
  const int mb = static_cast<int>(base.size());
  const int rb = static_cast<int>(xb.size());
  Eigen::VectorXd a = Eigen::VectorXd::Ones(rb);
  Eigen::RowVectorXd r = Eigen::RowVectorXd::Ones(rb);
  for (int j = 0; j < mb; ++j) a[j] = model_.entry(base[j], v), r[j] = model_.entry(v, base[j]);
  const Bordered step = border(b_inverse, xb, r, a, model_.entry(v, v), -model_.g()[v]);
  if (!step.ok) return {};
  const Eigen::VectorXd y = xb - step.ba * step.y;
  // The cones in their order: v at the moved one's place, or last; c last.
  const int at = moved >= 0 ? moved : mb;
  std::vector<int> cones = base;
  cones.insert(cones.begin() + at, v);
  Eigen::VectorXd x(rb + 1);
  x.head(at) = y.head(at);
  x[at] = step.y;
  x.segment(at + 1, rb - at) = y.tail(rb - at);
  return solution_of(cones, x);
}

void HeldSystem::remove(int i) {
  if (!valid_ || !(std::abs(inverse_(i, i)) > 0) || ++updates_ > kStepsBetweenFactorizations) {
    std::vector<int> cones = cones_;
    cones.erase(cones.begin() + i);
    reset(cones);
    return;
  }
  drop_index(i, inverse_, x_);
  cones_.erase(cones_.begin() + i);
}

void HeldSystem::add(int v, int moved) {
  std::vector<int> after = cones_;
  if (moved >= 0) {
    after[static_cast<size_t>(moved)] = v;
  } else {
    after.push_back(v);
  }
  if (!valid_ || ++updates_ > kStepsBetweenFactorizations ||
      (moved >= 0 && !(std::abs(inverse_(moved, moved)) > 0))) {
    reset(after);
    return;
  }
  if (moved >= 0) drop_index(moved, inverse_, x_);
  std::vector<int> base = cones_;
  if (moved >= 0) base.erase(base.begin() + moved);
  model_.solve_columns({v});
  const int mb = static_cast<int>(base.size());
  const int rb = static_cast<int>(x_.size());
  Eigen::VectorXd a = Eigen::VectorXd::Ones(rb);
  Eigen::RowVectorXd r = Eigen::RowVectorXd::Ones(rb);
  for (int j = 0; j < mb; ++j) a[j] = model_.entry(base[j], v), r[j] = model_.entry(v, base[j]);
  const Bordered step = border(inverse_, x_, r, a, model_.entry(v, v), -model_.g()[v]);
  if (!step.ok) {
    reset(after);
    return;
  }
  // The bordered inverse [B + B a r B / s, -B a / s; -r B / s, 1 / s], its new index moved to
  // v's place among the cones.
  const Eigen::RowVectorXd rb_row = r * inverse_;
  Eigen::MatrixXd grown(rb + 1, rb + 1);
  grown.topLeftCorner(rb, rb) = inverse_ + step.ba * rb_row / step.s;
  grown.topRightCorner(rb, 1) = -step.ba / step.s;
  grown.bottomLeftCorner(1, rb) = -rb_row / step.s;
  grown(rb, rb) = 1 / step.s;
  Eigen::VectorXd x(rb + 1);
  x.head(rb) = x_ - step.ba * step.y;
  x[rb] = step.y;
  const int at = moved >= 0 ? moved : mb;
  std::vector<int> order;  // new index -> grown's
  for (int j = 0; j < rb + 1; ++j) {
    if (j < at) {
      order.push_back(j);
    } else if (j == at) {
      order.push_back(rb);
    } else {
      order.push_back(j - 1);
    }
  }
  inverse_ = grown(order, order);
  x_ = x(order);
  cones_ = after;
}

}  // namespace ricci
