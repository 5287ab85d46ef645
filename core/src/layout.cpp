#include "ricci/layout.h"

#include <cmath>
#include <queue>

#include <Eigen/SparseCore>

#include "ricci/errors.h"
#include "ricci/geometry.h"

namespace ricci {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Direction angle of every halfedge, integrated over a breadth-first tree of faces.
std::vector<double> halfedge_directions(const Triangulation& mesh,
                                        const std::vector<double>& lengths) {
  const int nf = mesh.num_faces();
  std::vector<std::array<double, 3>> angle(nf);
  for (int f = 0; f < nf; ++f) {
    const std::array<double, 3> l = {lengths[mesh.face_edge(f, 0)], lengths[mesh.face_edge(f, 1)],
                                     lengths[mesh.face_edge(f, 2)]};
    const TriangleAngles t = corner_angles(Geometry::Euclidean, l);
    if (!t.valid) {
      throw InvalidArgumentError("layout: face " + std::to_string(f) +
                                 " violates the triangle inequality; lay out a converged metric");
    }
    angle[f] = t.angle;
  }
  std::vector<double> direction(3 * nf, 0.0);
  std::vector<char> placed(nf, 0);
  std::queue<int> queue;
  // Within a counter-clockwise face, halfedge c+1 turns left from halfedge c by the exterior
  // angle at their shared corner c+2: pi - theta_(c+2).
  auto fill_face = [&](int f, int c, double dir) {
    direction[3 * f + c] = dir;
    const int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
    direction[3 * f + c1] = dir + kPi - angle[f][c2];
    direction[3 * f + c2] = direction[3 * f + c1] + kPi - angle[f][c];
    placed[f] = 1;
    queue.push(f);
  };
  fill_face(0, 0, 0.0);
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop();
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * f + c);
      if (t < 0 || placed[t / 3]) continue;
      fill_face(t / 3, t % 3, direction[3 * f + c] + kPi);
    }
  }
  return direction;
}

}  // namespace

PlanarLayout layout_disk(const Triangulation& mesh, const std::vector<double>& lengths,
                         LinearSolverKind solver_kind) {
  if (!mesh.is_disk()) {
    throw InvalidArgumentError("layout: the planar layout needs a disk, but the mesh is a " +
                               mesh.topology_name() + "; cut it into a disk first");
  }
  if (static_cast<int>(lengths.size()) != mesh.num_edges()) {
    throw InvalidArgumentError("layout: one length per edge is needed");
  }
  const std::vector<double> direction = halfedge_directions(mesh, lengths);

  // Least squares: sum over halfedges |x_head - x_tail - l (cos, sin)|^2, vertex 0 pinned.
  const int n = mesh.num_vertices();
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n - 1, 2);
  auto row = [](int v) { return v - 1; };  // vertex 0 is pinned at the origin
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    const int a = mesh.halfedge_tail(h), b = mesh.halfedge_head(h);
    const double l = lengths[mesh.face_edge(h / 3, h % 3)];
    const Eigen::Vector2d e(l * std::cos(direction[h]), l * std::sin(direction[h]));
    if (a != 0) {
      triplets.emplace_back(row(a), row(a), 1.0);
      rhs.row(row(a)) -= e.transpose();
    }
    if (b != 0) {
      triplets.emplace_back(row(b), row(b), 1.0);
      rhs.row(row(b)) += e.transpose();
    }
    if (a != 0 && b != 0) {
      triplets.emplace_back(row(a), row(b), -1.0);
      triplets.emplace_back(row(b), row(a), -1.0);
    }
  }
  PlanarLayout layout;
  layout.position.assign(n, Eigen::Vector2d::Zero());
  if (n > 1) {
    Eigen::SparseMatrix<double> laplacian(n - 1, n - 1);
    laplacian.setFromTriplets(triplets.begin(), triplets.end());
    LinearSolver solver(solver_kind);
    solver.analyze(laplacian);
    if (!solver.factorize(laplacian)) throw SolverError("layout: the graph Laplacian is singular");
    const Eigen::MatrixXd x = solver.solve(rhs);
    for (int v = 1; v < n; ++v) layout.position[v] = x.row(row(v)).transpose();
  }
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& p : layout.position) centroid += p;
  centroid /= n;
  for (auto& p : layout.position) p -= centroid;

  layout.num_flipped_faces = count_flipped_faces(mesh, layout.position);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [i, j] = mesh.edge_vertices(e);
    const double err = std::abs((layout.position[i] - layout.position[j]).norm() / lengths[e] - 1);
    layout.max_relative_length_error = std::max(layout.max_relative_length_error, err);
  }
  return layout;
}

int count_flipped_faces(const Triangulation& mesh, const std::vector<Eigen::Vector2d>& position) {
  int flipped = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector2d a = position[mesh.face_vertex(f, 1)] - position[mesh.face_vertex(f, 0)];
    const Eigen::Vector2d b = position[mesh.face_vertex(f, 2)] - position[mesh.face_vertex(f, 0)];
    if (!(a.x() * b.y() - a.y() * b.x() > 0)) ++flipped;
  }
  return flipped;
}

std::vector<Eigen::Vector2d> normalized_texture_coordinates(
    const std::vector<Eigen::Vector2d>& position) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(INFINITY), hi = -lo;
  for (const auto& p : position) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  const Eigen::Vector2d offset = 0.5 * (Eigen::Vector2d::Ones() - (hi - lo) / extent);
  std::vector<Eigen::Vector2d> uv(position.size());
  for (size_t v = 0; v < position.size(); ++v) uv[v] = (position[v] - lo) / extent + offset;
  return uv;
}

}  // namespace ricci
