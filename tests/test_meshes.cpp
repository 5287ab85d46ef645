#include "test_meshes.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "ricci/io/mesh_io.h"
#include "ricci/mesh/geometry.h"

namespace ricci::test {

CompactMesh bumpy_disk(int n) {
  // The square grid on [-1,1]^2 mapped onto the unit disk by the elliptical grid map.
  CompactMesh grid = square_grid(n);
  std::vector<Eigen::Vector3d> p = grid.positions();
  for (auto& q : p) {
    const double x = 2 * q.x() - 1, y = 2 * q.y() - 1;
    const double u = x * std::sqrt(1 - y * y / 2), v = y * std::sqrt(1 - x * x / 2);
    q = Eigen::Vector3d(u, v, 0.3 * std::exp(-2 * (u * u + v * v)));
  }
  return CompactMesh(p, grid.faces());
}

CompactMesh square_grid(int n) {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::array<int, 3>> f;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) p.emplace_back(double(i) / n, double(j) / n, 0.0);
  }
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return CompactMesh(p, f);
}

CompactMesh torus(int n, int m, double major, double minor) {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::array<int, 3>> f;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double a = 2 * kPi * i / n, b = 2 * kPi * j / m;
      p.emplace_back((major + minor * std::cos(b)) * std::cos(a),
                     (major + minor * std::cos(b)) * std::sin(a), minor * std::sin(b));
    }
  }
  auto id = [n, m](int i, int j) { return ((i + n) % n) * m + (j + m) % m; };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return CompactMesh(p, f);
}

CompactMesh ellipsoid(int levels, double a, double b, double c) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& q : p) q.normalize();
  for (int level = 0; level < levels; ++level) {
    CompactMesh finer = subdivide_midpoint(CompactMesh(p, f), 1);
    p = finer.positions();
    f = finer.faces();
    for (auto& q : p) q.normalize();
  }
  for (auto& q : p) q = Eigen::Vector3d(a * q.x(), b * q.y(), c * q.z());
  return CompactMesh(p, f);
}

CompactMesh subdivide_midpoint(const CompactMesh& mesh, int levels) {
  std::vector<Eigen::Vector3d> p = mesh.positions();
  std::vector<std::array<int, 3>> f = mesh.faces();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int i, int j) {
      const std::pair<int, int> key(std::min(i, j), std::max(i, j));
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      p.push_back(0.5 * (p[i] + p[j]));
      return midpoint[key] = static_cast<int>(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> g;
    g.reserve(4 * f.size());
    for (const auto& t : f) {
      const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      g.push_back({t[0], ab, ca});
      g.push_back({t[1], bc, ab});
      g.push_back({t[2], ca, bc});
      g.push_back({ab, bc, ca});
    }
    f = std::move(g);
  }
  return CompactMesh(std::move(p), std::move(f));
}

std::string cgal_mesh_path(const std::string& name) {
  return std::string(RICCI_CGAL_DATA_DIR) + "/" + name;
}

CompactMesh cgal_mesh(const std::string& name) {
  return read_mesh(cgal_mesh_path(name));
}

std::vector<int> interior_rows(const CompactMesh& mesh) {
  std::vector<int> index(mesh.num_vertices(), -1);
  int n = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!mesh.is_boundary_vertex(v)) index[v] = n++;
  }
  return index;
}

SchemeOptions scheme_options(Scheme scheme, const CompactMesh& mesh) {
  SchemeOptions o;
  o.scheme = scheme;
  o.eps.resize(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) o.eps[v] = v % 3 - 1;
  return o;
}

FlowOptions without_flips() {
  FlowOptions o;
  o.edge_flips = EdgeFlips::Never;
  return o;
}

}  // namespace ricci::test
