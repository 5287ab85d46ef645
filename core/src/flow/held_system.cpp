#include "flow/held_system.h"

#include <cmath>

#include <Eigen/LU>

namespace ricci {

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
