#include "flow/metric.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

#include "mesh/two_threads.h"

namespace ricci {

namespace {

std::array<double, 3> face_lengths(const Triangulation& mesh, const MetricState& state, int f) {
  return {state.edges[mesh.face_edge(f, 0)].length, state.edges[mesh.face_edge(f, 1)].length,
          state.edges[mesh.face_edge(f, 2)].length};
}
}  // namespace

std::vector<double> MetricState::lengths() const {
  std::vector<double> l(edges.size());
  for (size_t e = 0; e < edges.size(); ++e) l[e] = edges[e].length;
  return l;
}

MetricState evaluate_lengths(const Triangulation& mesh, const ConformalStructure& structure,
                             const Eigen::VectorXd& u) {
  MetricState state;
  const Geometry g = structure.geometry;
  state.edges.resize(mesh.num_edges());
  const Eigen::VectorXd x = u.array().exp();
  int invalid_edges[2] = {0, 0};
  detail::in_two_halves(mesh.num_edges(), [&](int part, int begin, int end) {
    for (int e = begin; e < end; ++e) {
      const auto [i, j] = mesh.edge_vertices(e);
      state.edges[e] = edge_length_of_exponentials(g, x[i], x[j], structure.eps[i],
                                                   structure.eps[j], structure.eta[e]);
      invalid_edges[part] += !state.edges[e].valid;
    }
  });
  state.num_invalid_edges = invalid_edges[0] + invalid_edges[1];
  return state;
}

bool lengths_admit_triangles(const Triangulation& mesh, Geometry geometry,
                             const MetricState& state) {
  if (state.num_invalid_edges > 0) return false;
  int invalid[2] = {0, 0};
  detail::in_two_halves(mesh.num_faces(), [&](int part, int begin, int end) {
    for (int f = begin; f < end && invalid[part] == 0; ++f) {
      invalid[part] += !is_valid_triangle(geometry, face_lengths(mesh, state, f));
    }
  });
  return invalid[0] + invalid[1] == 0;
}

int first_halving_admitted(const Triangulation& mesh, const ConformalStructure& structure,
                           const Eigen::VectorXd& u, const Eigen::VectorXd& d,
                           const MetricState& at_whole_step, int last) {
  const Geometry g = structure.geometry;
  if (g != Geometry::Euclidean) return 0;
  // Face f at u + alpha d could be admitted: its triangle inequalities hold to a relative slack
  // of 1e-9, far above where this evaluation (its exponentials taken one by one) and
  // evaluate_lengths's (taken a vector at a time) can differ; an edge without a length counts as
  // admitted. So no halving that the whole test admits is judged otherwise here.
  const auto admitted = [&](int f, double alpha) {
    std::array<double, 3> l{};
    for (int c = 0; c < 3; ++c) {
      const int e = mesh.face_edge(f, c);
      const auto [i, j] = mesh.edge_vertices(e);
      const EdgeLength el = edge_length_of_exponentials(
          g, std::exp(u[i] + alpha * d[i]), std::exp(u[j] + alpha * d[j]), structure.eps[i],
          structure.eps[j], structure.eta[e]);
      if (!el.valid) return true;
      l[c] = el.length;
    }
    const double slack = 1 + 1e-9;
    return l[0] <= (l[1] + l[2]) * slack && l[1] <= (l[2] + l[0]) * slack &&
           l[2] <= (l[0] + l[1]) * slack;
  };
  int most = 0;  // the largest first admitted halving of the faces so far
  for (int f = 0; f < mesh.num_faces(); ++f) {
    bool whole = true;
    for (int c = 0; c < 3; ++c) whole = whole && at_whole_step.edges[mesh.face_edge(f, c)].valid;
    if (whole && is_valid_triangle(g, face_lengths(mesh, at_whole_step, f))) continue;
    // Admitted at `most` halvings: its first is no later. Else its first, from the start.
    if (most > 0 && admitted(f, std::ldexp(1.0, -most))) continue;
    int k = 1;
    while (k <= last && !admitted(f, std::ldexp(1.0, -k))) ++k;
    most = std::max(most, k);
    if (most > last) break;
  }
  return most;
}

void evaluate_angles(const Triangulation& mesh, Geometry geometry, MetricState& state) {
  state.faces.resize(mesh.num_faces());
  int invalid_faces[2] = {0, 0}, first_invalid[2] = {-1, -1};
  detail::in_two_halves(mesh.num_faces(), [&](int part, int begin, int end) {
    for (int f = begin; f < end; ++f) {
      state.faces[f] = corner_angles(geometry, face_lengths(mesh, state, f));
      if (!state.faces[f].valid && invalid_faces[part]++ == 0) first_invalid[part] = f;
    }
  });
  state.num_invalid_faces = invalid_faces[0] + invalid_faces[1];
  state.first_invalid_face = first_invalid[0] >= 0 ? first_invalid[0] : first_invalid[1];
}

MetricState evaluate_metric(const Triangulation& mesh, const ConformalStructure& structure,
                            const Eigen::VectorXd& u) {
  MetricState state = evaluate_lengths(mesh, structure, u);
  evaluate_angles(mesh, structure.geometry, state);
  return state;
}

void update_metric_at_edge(const Triangulation& mesh, const ConformalStructure& structure,
                           const Eigen::VectorXd& u, int e, MetricState& state) {
  const auto [i, j] = mesh.edge_vertices(e);
  state.num_invalid_edges -= !state.edges[e].valid;
  state.edges[e] = edge_length(structure.geometry, u[i], u[j], structure.eps[i], structure.eps[j],
                               structure.eta[e]);
  state.num_invalid_edges += !state.edges[e].valid;
  for (int f : mesh.edge_faces(e)) {
    if (f < 0) continue;
    state.num_invalid_faces -= !state.faces[f].valid;
    state.faces[f] = corner_angles(structure.geometry, face_lengths(mesh, state, f));
    if (!state.faces[f].valid && state.num_invalid_faces++ == 0) state.first_invalid_face = f;
  }
}

Eigen::VectorXd curvature(const Triangulation& mesh, const MetricState& state) {
  Eigen::VectorXd k(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) k[v] = mesh.is_boundary_vertex(v) ? kPi : 2 * kPi;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) k[mesh.face_vertex(f, c)] -= state.faces[f].angle[c];
  }
  return k;
}

Eigen::VectorXd curvature_round_off(const Triangulation& mesh, const MetricState& state) {
  Eigen::VectorXd noise = Eigen::VectorXd::Zero(mesh.num_vertices());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    std::array<double, 3> l = face_lengths(mesh, state, f);
    std::sort(l.begin(), l.end(), std::greater<double>());
    const double a = l[0], b = l[1], c = l[2];
    const double area4 =
        std::sqrt(std::max(0.0, (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c))));
    const double e = std::numeric_limits<double>::epsilon() * (a * a + b * b + c * c) /
                     std::max(area4, std::numeric_limits<double>::min());
    for (int corner = 0; corner < 3; ++corner) noise[mesh.face_vertex(f, corner)] += e;
  }
  return noise;
}

double total_area(const Triangulation& mesh, Geometry geometry, const MetricState& state) {
  double area = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    area += triangle_area(geometry, face_lengths(mesh, state, f), state.faces[f].angle);
  }
  return area;
}

}  // namespace ricci
