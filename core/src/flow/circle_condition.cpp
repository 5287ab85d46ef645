#include "flow/circle_condition.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ricci/mesh/errors.h"
#include "ricci/mesh/geometry.h"

namespace ricci::detail {

namespace {

// The boundary edge joining consecutive vertices a, b of a loop.
int boundary_edge(const Triangulation& mesh, const std::vector<std::vector<int>>& edges_at, int a,
                  int b) {
  for (int e : edges_at[a]) {
    const auto& ends = mesh.edge_vertices(e);
    if (ends[0] == b || ends[1] == b) return e;
  }
  throw InvalidArgumentError("boundary loop: no boundary edge joins vertices " + std::to_string(a) +
                             " and " + std::to_string(b));
}

}  // namespace

std::vector<std::vector<int>> loop_edges(const Triangulation& mesh) {
  std::vector<std::vector<int>> edges_at(mesh.num_vertices());
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (!mesh.is_boundary_edge(e)) continue;
    for (int v : mesh.edge_vertices(e)) edges_at[v].push_back(e);
  }
  std::vector<std::vector<int>> loops;
  for (const auto& loop : mesh.boundary_loops()) {
    std::vector<int> edges;
    for (size_t i = 0; i < loop.size(); ++i) {
      edges.push_back(boundary_edge(mesh, edges_at, loop[i], loop[(i + 1) % loop.size()]));
    }
    loops.push_back(std::move(edges));
  }
  return loops;
}

std::vector<double> central_angles(const std::vector<double>& l, std::vector<double>* weights) {
  double total = 0, longest = 0;
  for (double x : l) total += x, longest = std::max(longest, x);
  const auto sum_at = [&](double radius) {
    double s = 0;
    for (double x : l) s += 2 * std::asin(std::min(1.0, x / (2 * radius)));
    return s;
  };
  std::vector<double> theta(l.size());
  if (sum_at(longest / 2) < 2 * kPi) {
    for (size_t i = 0; i < l.size(); ++i) theta[i] = 2 * kPi * l[i] / total;
    if (weights) *weights = theta;
    return theta;
  }
  double lo = longest / 2, hi = total;  // sum_at(lo) >= 2 pi > sum_at(hi) (chords < arcs)
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (sum_at(mid) >= 2 * kPi ? lo : hi) = mid;
  }
  const double radius = 0.5 * (lo + hi);
  double sum = 0;
  for (size_t i = 0; i < l.size(); ++i) {
    theta[i] = 2 * std::asin(std::min(1.0, l[i] / (2 * radius)));
    sum += theta[i];
  }
  for (double& t : theta) t *= 2 * kPi / sum;
  if (weights) {
    weights->resize(l.size());
    // A chord near a diameter (angle near pi) has a steep derivative; past pi (by the rescaling's
    // rounding) tan would change sign.
    for (size_t i = 0; i < l.size(); ++i)
      (*weights)[i] = 2 * std::tan(0.5 * std::min(theta[i], kPi * (1 - 1e-9)));
  }
  return theta;
}

CircleCondition::CircleCondition(const Triangulation& mesh, int outer_loop)
    : num_vertices_(mesh.num_vertices()) {
  const auto edges = loop_edges(mesh);
  for (size_t c = 0; c < edges.size(); ++c) {
    Loop loop;
    loop.vertices = mesh.boundary_loops()[c];
    loop.edges = edges[c];
    loop.sign = static_cast<int>(c) == outer_loop ? 1.0 : -1.0;
    loops_.push_back(std::move(loop));
  }
}

void CircleCondition::set_target(const std::vector<double>& lengths,
                                 TargetCurvature& target) const {
  for (const Loop& loop : loops_) {
    std::vector<double> l;
    l.reserve(loop.edges.size());
    for (int e : loop.edges) l.push_back(lengths[e]);
    const std::vector<double> theta = central_angles(l);
    const size_t n = loop.vertices.size();
    for (size_t i = 0; i < n; ++i) {
      target.curvature[loop.vertices[i]] = loop.sign * 0.5 * (theta[(i + n - 1) % n] + theta[i]);
    }
  }
}

void CircleCondition::linearize(const std::vector<double>& lengths) {
  for (Loop& loop : loops_) {
    std::vector<double> l;
    l.reserve(loop.edges.size());
    for (int e : loop.edges) l.push_back(lengths[e]);
    central_angles(l, &loop.weights);
  }
}

Eigen::VectorXd CircleCondition::apply(const Eigen::VectorXd& du) const {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(num_vertices_);
  for (const Loop& loop : loops_) {
    const size_t n = loop.vertices.size();
    std::vector<double> dlog(n);
    double weighted = 0, total = 0;
    for (size_t i = 0; i < n; ++i) {
      dlog[i] = 0.5 * (du[loop.vertices[i]] + du[loop.vertices[(i + 1) % n]]);
      weighted += loop.weights[i] * dlog[i];
      total += loop.weights[i];
    }
    const double dlog_radius = total > 0 ? weighted / total : 0;
    for (size_t i = 0; i < n; ++i) {
      const double dangle = loop.weights[i] * (dlog[i] - dlog_radius);
      out[loop.vertices[i]] += loop.sign * 0.5 * dangle;
      out[loop.vertices[(i + 1) % n]] += loop.sign * 0.5 * dangle;
    }
  }
  return out;
}

}  // namespace ricci::detail
