#include "ricci/layout/layout.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "layout/corners.h"
#include "ricci/mesh/errors.h"

namespace ricci {

double orientation(Geometry geometry, const std::array<Eigen::Vector3d, 3>& p) {
  const Eigen::Vector3d u = p[1] - p[0], v = p[2] - p[0];
  // S2: det(p0, p1, p2) = p0 . (u x v); differences first keep the sign of small triangles.
  if (geometry == Geometry::Spherical) return u.cross(v).dot(p[0] + p[1] + p[2]) / 3;
  return u.x() * v.y() - u.y() * v.x();
}

std::vector<Eigen::Vector3d> vertex_positions(const Triangulation& mesh, const Layout& layout) {
  std::vector<Eigen::Vector3d> position(mesh.num_vertices(), Eigen::Vector3d::Zero());
  std::vector<char> set(mesh.num_vertices(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.face_vertex(f, c);
      if (!set[v]) position[v] = layout.corners[f][c], set[v] = 1;
    }
  }
  return position;
}

std::vector<std::array<Eigen::Vector3d, 3>> corners_on(const Triangulation& laid_out,
                                                       const Layout& layout,
                                                       const Triangulation& other) {
  // Flips keep edge indices: a face of `other` is a face of laid_out when its three edges bound
  // one, each still between its ends in `other` (vertex triples are not enough: after flips two
  // faces can have the same three vertices).
  std::map<std::array<int, 3>, int> face_of;  // sorted edges -> face of laid_out
  std::vector<std::vector<Eigen::Vector3d>> wedges(laid_out.num_vertices());
  for (int f = 0; f < laid_out.num_faces(); ++f) {
    std::array<int, 3> key = laid_out.face_edges(f);
    std::sort(key.begin(), key.end());
    face_of[key] = f;
    for (int c = 0; c < 3; ++c) wedges[laid_out.face_vertex(f, c)].push_back(layout.corners[f][c]);
  }
  const bool same_edges = laid_out.num_edges() == other.num_edges();
  std::vector<std::array<Eigen::Vector3d, 3>> corners(other.num_faces());
  for (int f = 0; f < other.num_faces(); ++f) {
    std::array<int, 3> key = other.face_edges(f);
    std::sort(key.begin(), key.end());
    auto same = same_edges ? face_of.find(key) : face_of.end();
    if (same != face_of.end()) {
      for (int e : key) {
        if (laid_out.edge_vertices(e) != other.edge_vertices(e)) same = face_of.end();
      }
    }
    for (int c = 0; c < 3; ++c) {
      const int v = other.face_vertex(f, c);
      if (same != face_of.end()) {
        corners[f][c] = layout.corners[same->second][detail::corner_of(laid_out, same->second, v)];
      } else if (c == 0) {
        corners[f][c] = wedges[v].front();
      } else {
        const Eigen::Vector3d& anchor = corners[f][0];
        corners[f][c] = *std::min_element(
            wedges[v].begin(), wedges[v].end(), [&](const auto& x, const auto& y) {
              return (x - anchor).squaredNorm() < (y - anchor).squaredNorm();
            });
      }
    }
  }
  return corners;
}

std::vector<Eigen::Vector3d> center_on_sphere(std::vector<Eigen::Vector3d> points, size_t count) {
  count = std::min(count, points.size());
  if (count == 0) return points;
  // phi_a(x) = ((1 - |a|^2)(x - a) - |x - a|^2 a) / (1 - 2 a.x + |a|^2 |x|^2): the automorphism
  // of the unit ball that moves a to 0, a Moebius map of the sphere.
  const auto centroid = [&]() {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < count; ++i) c += points[i];
    return Eigen::Vector3d(c / static_cast<double>(count));
  };
  for (int it = 0; it < 200; ++it) {
    const Eigen::Vector3d c = centroid();
    if (c.norm() < 1e-13) break;
    const Eigen::Vector3d a = c.norm() < 0.5 ? c : 0.5 * c.normalized();
    for (auto& x : points) {
      const double a2 = a.squaredNorm();
      x = ((1 - a2) * (x - a) - (x - a).squaredNorm() * a) /
          (1 - 2 * a.dot(x) + a2 * x.squaredNorm());
      x.normalize();
    }
  }
  return points;
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
