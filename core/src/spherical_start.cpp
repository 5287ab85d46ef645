#include "ricci/spherical_start.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>
#include <Eigen/SparseCore>

#include "ricci/errors.h"
#include "ricci/layout.h"
#include "ricci/linear_solver.h"
#include "ricci/ricci_flow.h"

namespace ricci {

namespace {

// Replaces the interior values of u by the solution of the graph Laplace equation with u's
// boundary values.
void harmonic_extension(const Triangulation& mesh, Eigen::VectorXd& u) {
  std::vector<int> row(mesh.num_vertices(), -1);
  int m = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!mesh.is_boundary_vertex(v)) row[v] = m++;
  }
  if (m == 0) return;
  std::vector<Eigen::Triplet<double>> t;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(m);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [i, j] = mesh.edge_vertices(e);
    for (int side = 0; side < 2; ++side) {
      const int v = side ? j : i, w = side ? i : j;
      if (row[v] < 0) continue;
      t.emplace_back(row[v], row[v], 1.0);
      if (row[w] >= 0) {
        t.emplace_back(row[v], row[w], -1.0);
      } else {
        b[row[v]] += u[w];
      }
    }
  }
  Eigen::SparseMatrix<double> laplacian(m, m);
  laplacian.setFromTriplets(t.begin(), t.end());
  LinearSolver solver(LinearSolverKind::Cholmod);
  solver.analyze(laplacian);
  if (!solver.factorize(laplacian)) throw SolverError("spherical start: singular Laplacian");
  const Eigen::VectorXd x = solver.solve(b);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (row[v] >= 0) u[v] = x[row[v]];
  }
}

// The lift from the puncture p (see stereographic_start). \throws when the punctured flow fails.
Eigen::VectorXd lift_from_puncture(const CompactMesh& mesh, const ConformalStructure& structure,
                                   int p) {
  const int n = mesh.num_vertices();

  // --- the punctured mesh (a disk) in its own vertex numbering
  std::vector<int> index(n, -1), original;
  std::vector<Eigen::Vector3d> positions;
  for (int v = 0; v < n; ++v) {
    if (v == p) continue;
    index[v] = static_cast<int>(original.size());
    original.push_back(v);
    positions.push_back(mesh.positions()[v]);
  }
  std::vector<std::array<int, 3>> faces;
  for (const auto& f : mesh.faces()) {
    if (f[0] != p && f[1] != p && f[2] != p)
      faces.push_back({index[f[0]], index[f[1]], index[f[2]]});
  }
  const CompactMesh disk(std::move(positions), std::move(faces));

  // --- flatten it. With p sent to infinity, the star triangles (p, a, b) become half-strips
  // exactly when lambda_pa e^(u_a / 2) is the same at every link vertex a: u_a = -2 log L_pa.
  SchemeOptions yamabe;
  yamabe.scheme = Scheme::Yamabe;
  ConformalStructure flat = initialize_scheme(disk, Geometry::Euclidean, yamabe);
  TargetCurvature target = TargetCurvature::free_boundary(disk);
  double mean_log = 0;
  int links = 0;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [i, j] = mesh.edge_vertices(e);
    if (i != p && j != p) continue;
    const int a = index[i == p ? j : i];
    flat.u0[a] = -2 * std::log(mesh.input_lengths()[e]);
    mean_log += flat.u0[a];
    ++links;
  }
  for (int v = 0; v < disk.num_vertices(); ++v) {
    if (disk.is_boundary_vertex(v)) flat.u0[v] -= mean_log / links;
  }
  // Interior u0: the harmonic extension of the link's values, so the first metric changes
  // smoothly towards the boundary instead of jumping at it.
  harmonic_extension(disk, flat.u0);
  const FlowResult r = run_ricci_flow(disk, flat, target);
  if (!r.converged) {
    throw ConvergenceError("spherical start: the punctured mesh did not flatten: " + r.failure,
                           r.iterations, r.residual);
  }
  const PlanarLayout layout = layout_disk(result_triangulation(disk, r), r.edge_lengths);

  // --- lift: S(x) = (2x, |x|^2 - 1) / (|x|^2 + 1), p at the pole; the similarity x -> s (x - t)
  // (the Moebius maps that fix the pole) is chosen so that the lifted vertices' centre of mass is
  // the origin, which spreads them evenly over the sphere.
  const auto lift = [](const Eigen::Vector2d& x) -> Eigen::Vector3d {
    const double s = x.squaredNorm();
    return Eigen::Vector3d(2 * x.x(), 2 * x.y(), s - 1) / (s + 1);
  };
  Eigen::Vector3d similarity(0, 0, 0);  // t_x, t_y, log s
  for (const auto& x : layout.position) similarity.head<2>() += x;
  similarity.head<2>() /= static_cast<double>(layout.position.size());
  {
    double mean_square = 0;
    for (const auto& x : layout.position) mean_square += (x - similarity.head<2>()).squaredNorm();
    similarity[2] = 0.5 * std::log(static_cast<double>(layout.position.size()) / mean_square);
  }
  const auto centroid = [&](const Eigen::Vector3d& q) -> Eigen::Vector3d {
    Eigen::Vector3d c(0, 0, 1);  // the pole
    for (const auto& x : layout.position) c += lift(std::exp(q[2]) * (x - q.head<2>()));
    return c / static_cast<double>(layout.position.size() + 1);
  };
  for (int it = 0; it < 30; ++it) {  // Newton with a finite-difference Jacobian, damped
    const Eigen::Vector3d c = centroid(similarity);
    if (c.norm() < 1e-6) break;
    Eigen::Matrix3d jacobian;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d dq = Eigen::Vector3d::Zero();
      dq[k] = 1e-6 * (k == 2 ? 1.0 : std::exp(-similarity[2]));
      jacobian.col(k) = (centroid(similarity + dq) - c) / dq[k];
    }
    Eigen::Vector3d step = jacobian.fullPivLu().solve(-c);
    if (!step.allFinite()) break;
    double alpha = 1;
    while (alpha > 1e-4 && !(centroid(similarity + alpha * step).norm() < c.norm())) alpha /= 2;
    similarity += alpha * step;
  }
  std::vector<Eigen::Vector3d> sphere(n, Eigen::Vector3d(0, 0, 1));
  for (int v = 0; v < disk.num_vertices(); ++v) {
    sphere[original[v]] =
        lift(std::exp(similarity[2]) * (layout.position[v] - similarity.head<2>()));
  }

  // --- u from the lifted lengths: sin(l_ij / 2) = sqrt(2 eta_ij) e^((ui + uj) / 2) with
  // 2 sin(l/2) = the chord, solved for u in the least-squares sense over all edges.
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [i, j] = mesh.edge_vertices(e);
    const double chord = (sphere[i] - sphere[j]).norm();
    const double b = 2 * (std::log(chord / 2) - 0.5 * std::log(2 * structure.eta[e]));  // ui + uj
    triplets.emplace_back(i, i, 1.0);
    triplets.emplace_back(j, j, 1.0);
    triplets.emplace_back(i, j, 1.0);
    triplets.emplace_back(j, i, 1.0);
    rhs[i] += b;
    rhs[j] += b;
  }
  Eigen::SparseMatrix<double> normal(n, n);
  normal.setFromTriplets(triplets.begin(), triplets.end());
  LinearSolver solver(LinearSolverKind::Cholmod);
  solver.analyze(normal);
  if (!solver.factorize(normal)) throw SolverError("spherical start: singular least-squares fit");
  return solver.solve(rhs);
}

}  // namespace

Eigen::VectorXd stereographic_start(const CompactMesh& mesh, const ConformalStructure& structure) {
  // Punctures to try: first the vertex of highest degree (its star is a well-shaped cap), then
  // the vertices whose link lengths vary least (the fixed u = -2 log L_pa on the link then varies
  // least, so the punctured flow starts from valid triangles).
  const int n = mesh.num_vertices();
  std::vector<double> lo(n, INFINITY), hi(n, -INFINITY);
  std::vector<int> degree(n, 0);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const double l = std::log(mesh.input_lengths()[e]);
    for (int v : mesh.edge_vertices(e)) {
      lo[v] = std::min(lo[v], l);
      hi[v] = std::max(hi[v], l);
      ++degree[v];
    }
  }
  const int highest =
      static_cast<int>(std::max_element(degree.begin(), degree.end()) - degree.begin());
  std::vector<int> candidates;
  for (int v = 0; v < n; ++v) {
    if (degree[v] >= 4 && v != highest) candidates.push_back(v);
  }
  const size_t more = std::min<size_t>(5, candidates.size());
  std::partial_sort(candidates.begin(), candidates.begin() + static_cast<long>(more),
                    candidates.end(), [&](int a, int b) { return hi[a] - lo[a] < hi[b] - lo[b]; });
  candidates.resize(more);
  candidates.insert(candidates.begin(), highest);
  std::string failures;
  for (int p : candidates) {
    try {
      return lift_from_puncture(mesh, structure, p);
    } catch (const Error& e) {
      failures = e.what();
    }
  }
  throw ConvergenceError(
      "spherical start: no puncture gave a flat punctured mesh (" + failures + ")", 0, INFINITY);
}

}  // namespace ricci
