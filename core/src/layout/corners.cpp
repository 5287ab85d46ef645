#include "layout/corners.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ricci/mesh/errors.h"

namespace ricci {

namespace detail {

std::vector<std::array<double, 3>> face_angles(const Triangulation& mesh, Geometry geometry,
                                               const std::vector<double>& lengths) {
  if (static_cast<int>(lengths.size()) != mesh.num_edges()) {
    throw InvalidArgumentError("layout: one length per edge is needed");
  }
  std::vector<std::array<double, 3>> angles(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const TriangleAngles t =
        corner_angles(geometry, {lengths[mesh.face_edge(f, 0)], lengths[mesh.face_edge(f, 1)],
                                 lengths[mesh.face_edge(f, 2)]});
    if (!t.valid) {
      throw InvalidArgumentError("layout: face " + std::to_string(f) + " is not a valid " +
                                 to_string(geometry) + " triangle; lay out a converged metric");
    }
    angles[f] = t.angle;
  }
  return angles;
}

void weld_corner_copies(const std::vector<std::array<int, 3>>& faces,
                        std::vector<std::array<Eigen::Vector3d, 3>>& corners) {
  double scale = 0;
  for (const auto& t : corners) {
    for (const Eigen::Vector3d& p : t) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  }
  const double tolerance = 1e-10 * scale;
  int num_vertices = 0;
  for (const auto& t : faces) num_vertices = std::max({num_vertices, t[0] + 1, t[1] + 1, t[2] + 1});
  std::vector<std::vector<Eigen::Vector3d>> copies(static_cast<size_t>(num_vertices));
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3d& p = corners[f][c];
      std::vector<Eigen::Vector3d>& seen = copies[static_cast<size_t>(faces[f][c])];
      const auto same = std::find_if(seen.begin(), seen.end(), [&](const Eigen::Vector3d& q) {
        return (p - q).cwiseAbs().maxCoeff() <= tolerance;
      });
      if (same == seen.end()) {
        seen.push_back(p);
      } else {
        p = *same;
      }
    }
  }
}

Eigen::Vector3d onto_drawn_side(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                const Eigen::Vector3d& z) {
  const Eigen::Vector3d side = q - p;
  if (!(side.squaredNorm() > 0)) return p;  // a side below double precision
  return p + std::clamp((z - p).dot(side) / side.squaredNorm(), 0.0, 1.0) * side;
}

Eigen::Vector3d disk_geodesic_point(const Eigen::Vector3d& p, const Eigen::Vector3d& q, double t) {
  // Hyperboloid points (x, y, w) with w^2 - x^2 - y^2 = 1.
  double x[3] = {0, 0, 0};
  for (const auto& [z, weight] : {std::pair{&p, 1 - t}, std::pair{&q, t}}) {
    const double r2 = z->x() * z->x() + z->y() * z->y(), k = weight / (1 - r2);
    x[0] += 2 * z->x() * k;
    x[1] += 2 * z->y() * k;
    x[2] += (1 + r2) * k;
  }
  const double n = std::sqrt(std::max(1e-300, x[2] * x[2] - x[0] * x[0] - x[1] * x[1]));
  const double w = x[2] / n;
  return {x[0] / n / (1 + w), x[1] / n / (1 + w), 0.0};
}

int corner_of(const Triangulation& mesh, int f, int v) {
  for (int c = 0; c < 3; ++c) {
    if (mesh.face_vertex(f, c) == v) return c;
  }
  return -1;
}

}  // namespace detail

}  // namespace ricci
