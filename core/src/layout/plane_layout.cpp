// E2 layouts of every topology: developed face by face with one position per wedge (a vertex's fan
// of faces on one side of the cut); where round-off accumulated too far, directions integrated
// across the faces and the least-squares fit of the edge vectors with one unknown per wedge.
#include <cmath>
#include <queue>

#include <Eigen/SparseCore>

#include "layout/layout_methods.h"
#include "mesh/mesh_checks.h"
#include "ricci/mesh/errors.h"

namespace ricci::detail {

namespace {

// Wedge of every corner: corners of one vertex joined across uncut interior edges share one. The
// first wedge of vertex v is v, further ones (on a cut) are numbered from num_vertices on, so a
// mesh without a cut has one wedge per vertex, numbered as its vertices.
std::vector<int> corner_wedges(const Triangulation& mesh, const std::vector<char>& cut,
                               int& num_wedges) {
  const int nf = mesh.num_faces();
  UnionFind corners(3 * nf);
  for (int h = 0; h < 3 * nf; ++h) {
    const int t = mesh.twin(h);
    if (t < h || cut[mesh.face_edge(h / 3, h % 3)]) continue;
    for (int v : {mesh.halfedge_tail(h), mesh.halfedge_head(h)}) {
      corners.unite(3 * (h / 3) + corner_of(mesh, h / 3, v),
                    3 * (t / 3) + corner_of(mesh, t / 3, v));
    }
  }
  std::vector<int> wedge_of_root(3 * nf, -1), wedge(3 * nf);
  std::vector<char> has_wedge(mesh.num_vertices(), 0);
  num_wedges = mesh.num_vertices();
  for (int k = 0; k < 3 * nf; ++k) {
    const int root = corners.find(k), v = mesh.face_vertex(k / 3, k % 3);
    if (wedge_of_root[root] < 0) wedge_of_root[root] = has_wedge[v] ? num_wedges++ : v;
    has_wedge[v] = 1;
    wedge[k] = wedge_of_root[root];
  }
  return wedge;
}

// Direction angle of every halfedge, integrated over a breadth-first tree of faces from face 0
// that does not cross the cut.
std::vector<double> halfedge_directions(const Triangulation& mesh,
                                        const std::vector<std::array<double, 3>>& angle,
                                        const std::vector<char>& cut) {
  const int nf = mesh.num_faces();
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
      if (t < 0 || placed[t / 3] || cut[mesh.face_edge(f, c)]) continue;
      fill_face(t / 3, t % 3, direction[3 * f + c] + kPi);
    }
  }
  return direction;
}

// Least squares: sum over halfedges |x_head - x_tail - l (cos, sin)|^2, wedge 0 pinned.
std::vector<Eigen::Vector2d> fit_edge_vectors(const Triangulation& mesh,
                                              const std::vector<double>& lengths,
                                              const std::vector<double>& direction,
                                              const std::vector<int>& wedge, int n,
                                              LinearSolverKind kind) {
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n - 1, 2);
  auto row = [](int w) { return w - 1; };
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    const int f = h / 3, c = h % 3;
    const int a = wedge[3 * f + (c + 1) % 3], b = wedge[3 * f + (c + 2) % 3];
    const double l = lengths[mesh.face_edge(f, c)];
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
  std::vector<Eigen::Vector2d> x(n, Eigen::Vector2d::Zero());
  if (n > 1) {
    Eigen::SparseMatrix<double> laplacian(n - 1, n - 1);
    laplacian.setFromTriplets(triplets.begin(), triplets.end());
    LinearSolver solver(kind);
    solver.analyze(laplacian);
    if (!solver.factorize(laplacian)) throw SolverError("layout: the graph Laplacian is singular");
    const Eigen::MatrixXd solution = solver.solve(rhs);
    for (int w = 1; w < n; ++w) x[w] = solution.row(row(w)).transpose();
  }
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& p : x) centroid += p;
  centroid /= n;
  for (auto& p : x) p -= centroid;
  return x;
}

double max_relative_length_error(const Triangulation& mesh, const std::vector<double>& lengths,
                                 const Layout& layout) {
  double error = 0;
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    const auto& p = layout.corners[h / 3];
    const double l = lengths[mesh.face_edge(h / 3, h % 3)];
    error = std::max(error, std::abs((p[(h % 3 + 1) % 3] - p[(h % 3 + 2) % 3]).norm() / l - 1));
  }
  return error;
}

}  // namespace

Layout plane_layout(const Triangulation& mesh, const std::vector<double>& lengths,
                    LinearSolverKind solver, double max_developed_error) {
  const int nf = mesh.num_faces();
  // Developed face by face (nearest to the seed first, develop()), each wedge at the mean of its
  // corners: exact up to the round-off accumulated along the development's tree, and no linear
  // solve (on a 267k-face disk 0.3 s against 1.4 s). Where that round-off exceeds
  // max_developed_error in some edge's length, the least-squares fit spreads it instead.
  Layout layout = develop(mesh, Geometry::Euclidean, lengths);
  if (nf == 0) return layout;
  int num_wedges = 0;
  const std::vector<int> wedge = corner_wedges(mesh, layout.cut.cut, num_wedges);
  std::vector<Eigen::Vector3d> x(num_wedges, Eigen::Vector3d::Zero());
  std::vector<int> count(num_wedges, 0);
  for (int k = 0; k < 3 * nf; ++k) {
    x[wedge[k]] += layout.corners[k / 3][k % 3];
    ++count[wedge[k]];
  }
  for (int w = 0; w < num_wedges; ++w) x[w] /= std::max(count[w], 1);
  for (int k = 0; k < 3 * nf; ++k) layout.corners[k / 3][k % 3] = x[wedge[k]];
  layout.max_relative_length_error = max_relative_length_error(mesh, lengths, layout);
  if (!(layout.max_relative_length_error <= max_developed_error)) {
    const std::vector<std::array<double, 3>> angle =
        face_angles(mesh, Geometry::Euclidean, lengths);
    const std::vector<double> direction = halfedge_directions(mesh, angle, layout.cut.cut);
    const std::vector<Eigen::Vector2d> fit =
        fit_edge_vectors(mesh, lengths, direction, wedge, num_wedges, solver);
    for (int k = 0; k < 3 * nf; ++k) {
      layout.corners[k / 3][k % 3] = Eigen::Vector3d(fit[wedge[k]].x(), fit[wedge[k]].y(), 0.0);
    }
    layout.max_relative_length_error = max_relative_length_error(mesh, lengths, layout);
  }
  glue_along_cut(mesh, layout);
  return layout;
}

}  // namespace ricci::detail
