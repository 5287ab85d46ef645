#include "flow/spherical_start.h"

#include "flow/metric.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/LU>
#include <Eigen/SparseCore>

#include "ricci/flow/flow_solver.h"
#include "ricci/layout/lay_out.h"
#include "ricci/layout/layout.h"
#include "ricci/linear/linear_solver.h"
#include "ricci/mesh/errors.h"
#include "ricci/mesh/geometry.h"

namespace ricci {

namespace {

// S(x) = (2x, |x|^2 - 1) / (|x|^2 + 1): the plane onto the unit sphere, infinity at the pole.
Eigen::Vector3d inverse_stereographic(const Eigen::Vector2d& x) {
  const double s = x.squaredNorm();
  return Eigen::Vector3d(2 * x.x(), 2 * x.y(), s - 1) / (s + 1);
}

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

// Yamabe (eps = 0): the conformal factors that fit the lifted vertices' chords best, in the
// least-squares sense over all edges: sin(l_ij / 2) = sqrt(2 eta_ij) e^((ui + uj) / 2) is linear
// in u after taking logarithms, with 2 sin(l / 2) = the chord.
Eigen::VectorXd fit_yamabe_to_chords(const Triangulation& mesh, const ConformalStructure& structure,
                                     const std::vector<Eigen::Vector3d>& sphere,
                                     const VertexOrder& order) {
  const int n = mesh.num_vertices();
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
  // Its pattern is the vertex graph's: the order found for it, where there is one.
  std::vector<int> rows;
  if (n >= kNestedDissectionRows && order.num_vertices() == n) {
    std::vector<int> row_of_vertex(static_cast<size_t>(n));
    std::iota(row_of_vertex.begin(), row_of_vertex.end(), 0);
    rows = order.rows(row_of_vertex);
  }
  solver.analyze(normal, rows.empty() ? nullptr : &rows);
  if (!solver.factorize(normal)) throw SolverError("spherical start: singular least-squares fit");
  return solver.solve(rhs);
}

// The mesh punctured at vertex p (a disk), in its own vertex numbering.
struct Punctured {
  CompactMesh disk;
  std::vector<int> original;    // per disk vertex, the mesh's vertex
  std::vector<int> index;       // per mesh vertex, the disk's (-1 for p)
  std::vector<int> kept_faces;  // per disk face, the mesh's face
};

Punctured puncture(const CompactMesh& mesh, int p) {
  const int n = mesh.num_vertices();
  std::vector<int> index(n, -1), original;
  std::vector<Eigen::Vector3d> positions;
  for (int v = 0; v < n; ++v) {
    if (v == p) continue;
    index[v] = static_cast<int>(original.size());
    original.push_back(v);
    positions.push_back(mesh.positions()[v]);
  }
  std::vector<std::array<int, 3>> faces;
  std::vector<int> kept_faces;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto& v = mesh.faces()[f];
    if (v[0] == p || v[1] == p || v[2] == p) continue;
    faces.push_back({index[v[0]], index[v[1]], index[v[2]]});
    kept_faces.push_back(f);
  }
  return {CompactMesh(std::move(positions), std::move(faces)), std::move(original),
          std::move(index), std::move(kept_faces)};
}

// The E2 structure of the punctured mesh with the same radii, and with the same eta where the
// scheme takes eta from the input lengths (then the flat metric starts at the input lengths; S2's
// eta would give the chords, and thin triangles would fail). A prescribed eta (tangential,
// Thurston) is kept: inversive distances are invariant under the Moebius maps, so the
// stereographic image of the round-sphere pattern is a flat pattern of the punctured mesh with
// that eta. With p sent to infinity by an inversion centred at p, a vertex at distance L_pa from
// p is scaled by 1 / L_pa^2: its u is fixed at u0_a - 2 log L_pa on the link, which makes the
// star triangles (p, a, b) half-strips in the Yamabe case; the interior's shift is the harmonic
// extension of the link's, so the first metric changes smoothly towards the boundary.
ConformalStructure flat_structure(const CompactMesh& mesh, const ConformalStructure& structure,
                                  const Punctured& punctured, int p) {
  const int n = mesh.num_vertices();
  const CompactMesh& disk = punctured.disk;
  const double scale = structure.length_scale;
  Eigen::VectorXd radius_u(n);  // E2's u for S2's initial radii
  for (int v = 0; v < n; ++v)
    radius_u[v] = std::log(radius_from_conformal_factor(Geometry::Spherical, structure.u0[v]));
  bool from_input = true;
  for (int e = 0; e < mesh.num_edges() && from_input; ++e) {
    const auto [i, j] = mesh.edge_vertices(e);
    const double l = edge_length(Geometry::Spherical, structure.u0[i], structure.u0[j],
                                 structure.eps[i], structure.eps[j], structure.eta[e])
                         .length;
    from_input = std::abs(l - scale * mesh.input_lengths()[e]) <= 1e-9 * l;
  }
  ConformalStructure flat;
  flat.geometry = Geometry::Euclidean;
  flat.eps.resize(disk.num_vertices());
  for (int v = 0; v < disk.num_vertices(); ++v) flat.eps[v] = structure.eps[punctured.original[v]];
  flat.eta.assign(disk.num_edges(), 0);
  for (size_t k = 0; k < punctured.kept_faces.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      const int e = mesh.face_edge(punctured.kept_faces[k], c);
      const auto [i, j] = mesh.edge_vertices(e);
      flat.eta[disk.face_edge(static_cast<int>(k), c)] =
          from_input ? conformal_structure_from_length(
                           Geometry::Euclidean, scale * mesh.input_lengths()[e], radius_u[i],
                           radius_u[j], structure.eps[i], structure.eps[j])
                     : structure.eta[e];
    }
  }
  Eigen::VectorXd shift = Eigen::VectorXd::Zero(disk.num_vertices());
  double mean_shift = 0;
  int links = 0;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [i, j] = mesh.edge_vertices(e);
    if (i != p && j != p) continue;
    const int a = punctured.index[i == p ? j : i];
    shift[a] = -2 * std::log(mesh.input_lengths()[e]);
    mean_shift += shift[a];
    ++links;
  }
  for (int v = 0; v < disk.num_vertices(); ++v) {
    if (disk.is_boundary_vertex(v)) shift[v] -= mean_shift / links;
  }
  harmonic_extension(disk, shift);
  flat.u0.resize(disk.num_vertices());
  for (int v = 0; v < disk.num_vertices(); ++v)
    flat.u0[v] = radius_u[punctured.original[v]] + shift[v];
  return flat;
}

// The similarity x -> s (x - t) (the Moebius maps that fix the pole) under which the lifted points
// and the pole have their centre of mass at the origin, which spreads them evenly over the sphere;
// as (t_x, t_y, log s).
Eigen::Vector3d centring_similarity(const std::vector<Eigen::Vector2d>& plane) {
  const double count = static_cast<double>(plane.size());
  Eigen::Vector3d q(0, 0, 0);
  for (const auto& x : plane) q.head<2>() += x;
  q.head<2>() /= count;
  double mean_square = 0;
  for (const auto& x : plane) mean_square += (x - q.head<2>()).squaredNorm();
  q[2] = 0.5 * std::log(count / mean_square);
  const auto centroid = [&](const Eigen::Vector3d& r) -> Eigen::Vector3d {
    Eigen::Vector3d c(0, 0, 1);  // the pole
    for (const auto& x : plane) c += inverse_stereographic(std::exp(r[2]) * (x - r.head<2>()));
    return c / (count + 1);
  };
  for (int it = 0; it < 30; ++it) {  // Newton with a finite-difference Jacobian, damped
    const Eigen::Vector3d c = centroid(q);
    if (c.norm() < 1e-6) break;
    Eigen::Matrix3d jacobian;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d dq = Eigen::Vector3d::Zero();
      dq[k] = 1e-6 * (k == 2 ? 1.0 : std::exp(-q[2]));
      jacobian.col(k) = (centroid(q + dq) - c) / dq[k];
    }
    Eigen::Vector3d step = jacobian.fullPivLu().solve(-c);
    if (!step.allFinite()) break;
    double alpha = 1;
    while (alpha > 1e-4 && !(centroid(q + alpha * step).norm() < c.norm())) alpha /= 2;
    q += alpha * step;
  }
  return q;
}

// u_p: the best fit of the lifted lengths of p's edges, by a scan refined by golden sections.
double fit_puncture(const CompactMesh& mesh, const ConformalStructure& structure,
                    const std::vector<Eigen::Vector3d>& sphere, const Eigen::VectorXd& u, int p) {
  std::vector<int> star;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [i, j] = mesh.edge_vertices(e);
    if (i == p || j == p) star.push_back(e);
  }
  const auto misfit = [&](double up) {
    double sum = 0;
    for (int e : star) {
      const auto [i, j] = mesh.edge_vertices(e);
      const int a = i == p ? j : i;
      const double lifted = 2 * std::asin(std::min(1.0, (sphere[a] - sphere[p]).norm() / 2));
      const EdgeLength l = edge_length(Geometry::Spherical, up, u[a], structure.eps[p],
                                       structure.eps[a], structure.eta[e]);
      sum += l.valid ? (l.length - lifted) * (l.length - lifted) : 10;
    }
    return sum;
  };
  double best = structure.u0[p], best_misfit = misfit(best);
  for (double up = -30; up <= 5; up += 0.05) {
    const double m = misfit(up);
    if (m < best_misfit) best = up, best_misfit = m;
  }
  double lo = best - 0.05, hi = best + 0.05;
  for (int it = 0; it < 60; ++it) {
    const double a = lo + 0.382 * (hi - lo), b = lo + 0.618 * (hi - lo);
    if (misfit(a) < misfit(b)) {
      hi = b;
    } else {
      lo = a;
    }
  }
  return 0.5 * (lo + hi);
}

// The lift from the puncture p (see stereographic_start). \throws when the punctured flow fails.
Eigen::VectorXd lift_from_puncture(const CompactMesh& mesh, const ConformalStructure& structure,
                                   int p, const VertexOrder& order) {
  const Punctured punctured = puncture(mesh, p);
  const CompactMesh& disk = punctured.disk;
  ConformalStructure flat = flat_structure(mesh, structure, punctured, p);
  // The shifted u can leave triangles of the input's triangulation invalid (a sliver in the
  // puncture's link): the flow then starts from the unshifted u, whose metric is the input's,
  // and walks to the shifted one with edge flips before Newton.
  const Eigen::VectorXd shifted = flat.u0;
  const bool walk = !evaluate_metric(disk, flat, shifted).valid();
  if (walk) {
    for (int v = 0; v < disk.num_vertices(); ++v) {
      flat.u0[v] = std::log(
          radius_from_conformal_factor(Geometry::Spherical, structure.u0[punctured.original[v]]));
    }
  }
  RicciFlowSolver solver(disk, flat, FlowOptions(), order.restricted(punctured.original));
  const FlowResult r =
      solver.solve(TargetCurvature::free_boundary(disk), walk ? &shifted : nullptr);
  if (!r.converged) {
    throw ConvergenceError("spherical start: the punctured mesh did not flatten: " + r.failure,
                           r.iterations, r.residual);
  }
  const Triangulation& flattened = result_triangulation(disk, r);
  std::vector<Eigen::Vector2d> plane;  // per vertex of the disk
  for (const Eigen::Vector3d& x :
       vertex_positions(flattened, lay_out(flattened, Geometry::Euclidean, r.edge_lengths))) {
    plane.push_back(x.head<2>());
  }
  // Lifted with p at the pole, after the similarity that centres the lift.
  const Eigen::Vector3d q = centring_similarity(plane);
  const double s = std::exp(q[2]);
  std::vector<Eigen::Vector3d> sphere(mesh.num_vertices(), Eigen::Vector3d(0, 0, 1));
  for (int v = 0; v < disk.num_vertices(); ++v)
    sphere[punctured.original[v]] = inverse_stereographic(s * (plane[v] - q.head<2>()));
  if (is_yamabe(structure)) return fit_yamabe_to_chords(mesh, structure, sphere, order);

  // u on the sphere: the projection scales lengths at y by 2 / (1 + |y|^2), and the similarity by
  // s, so a small circle at x becomes e^u s / (1 + |y|^2) on the sphere, where the length laws
  // agree with E2's to first order for chords 2 sin(l / 2), hence tan(r / 2).
  Eigen::VectorXd u(mesh.num_vertices());
  for (int v = 0; v < disk.num_vertices(); ++v) {
    const Eigen::Vector2d y = s * (plane[v] - q.head<2>());
    u[punctured.original[v]] = r.u[v] + std::log(s) - std::log1p(y.squaredNorm());
  }
  u[p] = fit_puncture(mesh, structure, sphere, u, p);
  return u;
}

}  // namespace

std::optional<Eigen::VectorXd> flow_start(const CompactMesh& mesh,
                                          const ConformalStructure& structure,
                                          const TargetCurvature& target, const FlowOptions& options,
                                          const VertexOrder& order) {
  if (!options.stereographic_start || structure.geometry != Geometry::Spherical ||
      !mesh.is_closed() || mesh.genus() != 0 || target.num_fixed() > 0) {
    return std::nullopt;
  }
  try {
    return stereographic_start(mesh, structure, order);
  } catch (const Error&) {
    return std::nullopt;  // no puncture flattened: the direct flow may still converge
  }
}

Eigen::VectorXd stereographic_start(const CompactMesh& mesh, const ConformalStructure& structure,
                                    const VertexOrder& order) {
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
      return lift_from_puncture(mesh, structure, p, order);
    } catch (const Error& e) {
      failures = e.what();
    }
  }
  throw ConvergenceError(
      "spherical start: no puncture gave a flat punctured mesh (" + failures + ")", 0, INFINITY);
}

}  // namespace ricci
