#include "layout/corners.h"

#include <algorithm>
#include <cmath>
#include <complex>
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
  const double tolerance = 1e-13 * scale;
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
  // With p moved to the centre, the geodesic is the ray to q's image at distance D, and the
  // hyperboloid point (1 - t) (0, 0, 1) + t (sinh D u, cosh D) lies at distance s along it with
  // tanh s = t sinh D / (1 - t + t cosh D); in terms of r = tanh(D / 2), tanh(s / 2) = A / (B +
  // sqrt(B^2 - A^2)) with A = 2 t r, B = (1 - t)(1 - r^2) + t (1 + r^2). In long double: near the
  // rim, 1 - conj(p) q cancels, and normalizing the hyperboloid point in its own coordinates
  // (w^2 - x^2 - y^2 = 1 from w ~ e^d) put the point off the geodesic by e^(2 d) roundings
  // (occt-head.stl at distance 6: new vertices off their final side by 5e-12, angle sums off by
  // 3e-8 at pieces 3e-4 wide).
  using LongComplex = std::complex<long double>;
  const LongComplex a(p.x(), p.y()), b(q.x(), q.y()), one = 1;
  const LongComplex moved = (b - a) / (one - std::conj(a) * b);
  const long double r = std::abs(moved), w = t;
  if (!(r > 0)) return p;
  // B^2 - A^2 as (B - A)(B + A), B - A = (1 - t)(1 - r^2) + t (1 - r)^2: no cancellation where t
  // is near 1 on a long side.
  const long double A = 2 * w * r, B = (1 - w) * (1 - r * r) + w * (1 + r * r);
  const long double below = (1 - w) * (1 - r * r) + w * (1 - r) * (1 - r);
  const long double half = A / (B + std::sqrt(std::max(below * (B + A), 0.0L)));
  const LongComplex z = moved * (half / r);
  const LongComplex back = (z + a) / (one + std::conj(a) * z);
  return {static_cast<double>(back.real()), static_cast<double>(back.imag()), 0.0};
}

int corner_of(const Triangulation& mesh, int f, int v) {
  for (int c = 0; c < 3; ++c) {
    if (mesh.face_vertex(f, c) == v) return c;
  }
  return -1;
}

}  // namespace detail

}  // namespace ricci
