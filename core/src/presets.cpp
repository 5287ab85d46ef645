#include "ricci/presets.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "ricci/errors.h"

namespace ricci {

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

// Per loop, the boundary edges in loop order: edge i joins vertex i and vertex i + 1.
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

// Central angles of chords of lengths l on one circle, summing to 2 pi: 2 asin(l / 2R) with R
// by bisection. When no such circle has its centre inside the polygon (one chord longer than
// the rest together allow), the angles fall back to proportional to length.
std::vector<double> central_angles(const std::vector<double>& l) {
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
  return theta;
}

}  // namespace

std::string to_string(TargetPreset p) {
  switch (p) {
    case TargetPreset::Automatic:
      return "auto";
    case TargetPreset::UnitDisk:
      return "disk";
    case TargetPreset::FreeBoundary:
      return "free-boundary";
    case TargetPreset::Zero:
      return "zero";
    case TargetPreset::Values:
      return "values";
  }
  return "?";
}

TargetPreset target_preset_from_string(const std::string& name) {
  for (TargetPreset p : {TargetPreset::Automatic, TargetPreset::UnitDisk,
                         TargetPreset::FreeBoundary, TargetPreset::Zero, TargetPreset::Values}) {
    if (to_string(p) == name) return p;
  }
  throw InvalidArgumentError("unknown target '" + name +
                             "'; choose auto, disk, free-boundary, zero or values");
}

Geometry preset_geometry(const Triangulation& mesh, TargetPreset preset) {
  switch (preset) {
    case TargetPreset::Automatic:
      return automatic_preset(mesh).second;
    case TargetPreset::Zero: {
      const int chi = mesh.euler_characteristic();
      if (chi < 0) return Geometry::Hyperbolic;
      return mesh.is_closed() && chi > 0 ? Geometry::Spherical : Geometry::Euclidean;
    }
    default:  // UnitDisk, FreeBoundary; Values are decided by geometry_for_target
      return Geometry::Euclidean;
  }
}

std::pair<TargetPreset, Geometry> automatic_preset(const Triangulation& mesh) {
  const TargetPreset preset =
      !mesh.is_closed() && mesh.genus() == 0 ? TargetPreset::UnitDisk : TargetPreset::Zero;
  return {preset, preset_geometry(mesh, preset)};
}

Geometry geometry_for_target(const CompactMesh& mesh, const TargetCurvature& target) {
  if (target.num_fixed() > 0) return Geometry::Euclidean;
  double sum = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) sum += target.curvature[v];
  const double two_pi_chi = 2 * kPi * mesh.euler_characteristic();
  const double slack = 1e-9 * (std::max(1.0, std::abs(two_pi_chi)) + std::abs(sum));
  if (std::abs(sum - two_pi_chi) <= slack) return Geometry::Euclidean;
  return sum > two_pi_chi ? Geometry::Hyperbolic : Geometry::Spherical;
}

TargetCurvature cone_target(const CompactMesh& mesh, const std::vector<Cone>& cones) {
  TargetCurvature t = TargetCurvature::zero(mesh);
  std::set<int> seen;
  for (const Cone& c : cones) {
    if (c.vertex < 0 || c.vertex >= mesh.num_vertices()) {
      throw InvalidTargetError("cone at vertex " + std::to_string(c.vertex) +
                               ": the mesh has vertices 0.." +
                               std::to_string(mesh.num_vertices() - 1));
    }
    if (!seen.insert(c.vertex).second) {
      throw InvalidTargetError("cone at vertex " + std::to_string(c.vertex) +
                               " is given twice; give each vertex once");
    }
    if (!(c.angle > 0) || !std::isfinite(c.angle)) {
      throw InvalidTargetError("cone at vertex " + std::to_string(c.vertex) +
                               ": the angle must be positive and finite");
    }
    t.curvature[c.vertex] = (mesh.is_boundary_vertex(c.vertex) ? kPi : 2 * kPi) - c.angle;
  }
  return t;
}

int outer_boundary_loop(const Triangulation& mesh, const std::vector<double>& lengths) {
  const auto loops = loop_edges(mesh);
  int best = -1;
  double best_length = -1;
  for (size_t c = 0; c < loops.size(); ++c) {
    double length = 0;
    for (int e : loops[c]) length += lengths[e];
    if (length > best_length) best = static_cast<int>(c), best_length = length;
  }
  return best;
}

TargetCurvature circle_boundary_target(const Triangulation& mesh,
                                       const std::vector<double>& lengths, int outer_loop) {
  TargetCurvature t;
  t.curvature = Eigen::VectorXd::Zero(mesh.num_vertices());
  t.fixed.assign(mesh.num_vertices(), 0);
  const auto loops = loop_edges(mesh);
  for (size_t c = 0; c < loops.size(); ++c) {
    std::vector<double> l;
    for (int e : loops[c]) l.push_back(lengths[e]);
    const std::vector<double> theta = central_angles(l);
    const double sign = static_cast<int>(c) == outer_loop ? 1.0 : -1.0;
    const auto& vertices = mesh.boundary_loops()[c];
    const size_t n = vertices.size();
    for (size_t i = 0; i < n; ++i) {
      t.curvature[vertices[i]] = sign * 0.5 * (theta[(i + n - 1) % n] + theta[i]);
    }
  }
  return t;
}

}  // namespace ricci
