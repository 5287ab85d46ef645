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
// (co)variances: the constant c drops out.
double LinearConeModel::distortion(const std::vector<int>& cones, const Eigen::VectorXd& k) const {
  double d2 = g_square_ - g_sum_ * g_sum_;
  for (size_t i = 0; i < cones.size(); ++i) {
    const int si = slot_of_[cones[i]];
    d2 += 2 * k[i] * (with_g_[si] - sum_[si] * g_sum_);
    for (size_t j = 0; j < cones.size(); ++j) {
      const int sj = slot_of_[cones[j]];
      d2 += k[i] * k[j] * (gram_(si, sj) - sum_[si] * sum_[sj]);
    }
  }
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
