#include "ricci/spherical_start.h"

#include <algorithm>
#include <cmath>

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

}  // namespace

Eigen::VectorXd stereographic_start(const CompactMesh& mesh, const ConformalStructure& structure) {
  const int n = mesh.num_vertices();
  // The puncture: the vertex of highest degree, so the removed star is a well-shaped cap.
  std::vector<int> degree(n, 0);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    for (int v : mesh.edge_vertices(e)) ++degree[v];
  }
  const int p = static_cast<int>(std::max_element(degree.begin(), degree.end()) - degree.begin());

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

  // --- centre and scale, then lift: S(x) = (2x, |x|^2 - 1) / (|x|^2 + 1); p goes to the pole.
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const auto& x : layout.position) centre += x;
  centre /= static_cast<double>(layout.position.size());
  double mean_square = 0;
  for (const auto& x : layout.position) mean_square += (x - centre).squaredNorm();
  const double scale = std::sqrt(static_cast<double>(layout.position.size()) / mean_square);
  std::vector<Eigen::Vector3d> sphere(n, Eigen::Vector3d(0, 0, 1));
  for (int v = 0; v < disk.num_vertices(); ++v) {
    const Eigen::Vector2d x = (layout.position[v] - centre) * scale;
    const double s = x.squaredNorm();
    sphere[original[v]] = Eigen::Vector3d(2 * x.x(), 2 * x.y(), s - 1) / (s + 1);
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

}  // namespace ricci
