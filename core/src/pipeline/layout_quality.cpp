#include "ricci/pipeline/layout_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "ricci/layout/layout.h"
#include "ricci/mesh/geometry.h"

namespace ricci {

double quantile(std::vector<double> x, double q) {
  if (x.empty()) return 1;
  const size_t k = std::min(x.size() - 1, static_cast<size_t>(q * static_cast<double>(x.size())));
  std::nth_element(x.begin(), x.begin() + static_cast<long>(k), x.end());
  return x[k];
}

namespace {

double triangle_area(const std::array<double, 3>& l) {
  if (!(l[2] > 0)) return 0;  // collapsed
  return 0.5 * l[2] * std::abs(triangle_apex(l[2], l[1], l[0])[1]);
}

std::array<double, 3> side_lengths(const std::array<Eigen::Vector3d, 3>& p) {
  return {(p[2] - p[1]).norm(), (p[0] - p[2]).norm(), (p[1] - p[0]).norm()};
}

}  // namespace

LayoutQuality measure_layout(const CompactMesh& mesh, Geometry geometry, const FlowResult& result,
                             const std::vector<std::array<Eigen::Vector3d, 3>>& corners) {
  std::vector<std::array<double, 3>> sides(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) sides[f][c] = mesh.input_lengths()[mesh.face_edge(f, c)];
  }
  return measure_layout(sides, geometry, result, corners);
}

std::vector<std::array<double, 3>> face_sides(const std::vector<Eigen::Vector3d>& positions,
                                              const std::vector<std::array<int, 3>>& faces) {
  std::vector<std::array<double, 3>> sides(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      sides[f][c] = (positions[faces[f][(c + 1) % 3]] - positions[faces[f][(c + 2) % 3]]).norm();
    }
  }
  return sides;
}

bool orientation_unresolved(const std::array<Eigen::Vector3d, 3>& p) {
  const Eigen::Vector3d u = p[1] - p[0], v = p[2] - p[0];
  const double magnitude = std::max({p[0].norm(), p[1].norm(), p[2].norm()});
  const double noise = 64 * 2.220446049250313e-16 * magnitude * (u.norm() + v.norm());
  return u.cross(v).norm() <= noise;
}

LayoutQuality measure_layout(const std::vector<std::array<double, 3>>& input_sides,
                             Geometry geometry, const FlowResult& result,
                             const std::vector<std::array<Eigen::Vector3d, 3>>& corners) {
  LayoutQuality q;
  int with_target = 0;
  for (int v = 0; v < result.target.size(); ++v) {
    if (std::isnan(result.target[v])) continue;
    const double e = std::abs(result.curvature[v] - result.target[v]);
    q.max_curvature_error = std::max(q.max_curvature_error, e);
    q.mean_curvature_error += e;
    ++with_target;
  }
  if (with_target > 0) q.mean_curvature_error /= with_target;
  if (corners.empty()) return q;

  const int nf = static_cast<int>(input_sides.size());
  std::vector<double> ratio(nf), input_area(nf), layout_area(nf);
  double input_total = 0, layout_total = 0;
  for (int f = 0; f < nf; ++f) {
    const std::array<double, 3>& from = input_sides[f];
    const auto& p = corners[f];
    const std::array<double, 3> to = side_lengths(p);
    ratio[f] = quasi_conformal_ratio(from, to);
    input_area[f] = triangle_area(from);
    layout_area[f] = triangle_area(to);
    input_total += input_area[f];
    layout_total += layout_area[f];
    if (!(orientation(geometry, p) > 0) && !orientation_unresolved(p)) {
      if (q.flipped_faces++ == 0) q.first_flipped_face = f;
    }
  }
  std::vector<double> area_ratio(nf);
  for (int f = 0; f < nf; ++f) {
    const bool positive = orientation(geometry, corners[f]) > 0;
    if ((layout_area[f] <= 1e-12 * layout_total / nf && positive) ||
        (!positive && orientation_unresolved(corners[f]))) {
      if (q.collapsed_faces++ == 0) q.first_collapsed_face = f;
    }
    area_ratio[f] = (layout_area[f] / layout_total) / (input_area[f] / input_total);
  }
  q.quasi_conformal_median = quantile(ratio, 0.5);
  q.quasi_conformal_p95 = quantile(ratio, 0.95);
  q.quasi_conformal_max = *std::max_element(ratio.begin(), ratio.end());
  q.area_ratio_p5 = quantile(area_ratio, 0.05);
  q.area_ratio_median = quantile(area_ratio, 0.5);
  q.area_ratio_p95 = quantile(area_ratio, 0.95);
  return q;
}

}  // namespace ricci
