#include "ricci/model_layout.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>
#include <string>

#include <Eigen/Geometry>

#include "ricci/errors.h"

namespace ricci {

namespace {

using Complex = std::complex<double>;

Complex to_complex(const Eigen::Vector3d& p) {
  return {p.x(), p.y()};
}
Eigen::Vector3d from_complex(Complex z) {
  return {z.real(), z.imag(), 0.0};
}

// The Poincare disk's isometry z -> (z - p) / (1 - conj(p) z), which moves p to 0.
DiskIsometry move_to_origin(Complex p) {
  const double s = std::sqrt(1 - std::norm(p));
  return {Geometry::Hyperbolic, 1 / s, -p / s};
}

// C such that (A, B, C) is counter-clockwise, |AC| = l_ac and the angle at A is alpha.
Eigen::Vector3d place_third(Geometry g, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            double l_ac, double alpha) {
  switch (g) {
    case Geometry::Euclidean: {
      const Complex dir = std::polar(1.0, std::arg(to_complex(b) - to_complex(a)) + alpha);
      return from_complex(to_complex(a) + l_ac * dir);
    }
    case Geometry::Hyperbolic: {
      const DiskIsometry m = move_to_origin(to_complex(a));
      const Complex c = std::polar(std::tanh(l_ac / 2), std::arg(m(to_complex(b))) + alpha);
      return from_complex(m.inverse()(c));
    }
    case Geometry::Spherical: {
      const Eigen::Vector3d t = (b - a.dot(b) * a).normalized();
      const Eigen::Vector3d turned = std::cos(alpha) * t + std::sin(alpha) * a.cross(t);
      return (std::cos(l_ac) * a + std::sin(l_ac) * turned).normalized();
    }
  }
  return a;
}

double orientation(Geometry g, const std::array<Eigen::Vector3d, 3>& p) {
  if (g == Geometry::Spherical) return p[0].dot(p[1].cross(p[2]));
  const Eigen::Vector3d u = p[1] - p[0], v = p[2] - p[0];
  return u.x() * v.y() - u.y() * v.x();
}

// The face deepest inside the cut disk: farthest, in faces, from every cut and boundary edge.
int deepest_face(const Triangulation& mesh, const std::vector<char>& cut) {
  const int nf = mesh.num_faces();
  std::vector<int> depth(nf, -1);
  std::queue<int> queue;
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int e = mesh.face_edge(f, c);
      if (mesh.is_boundary_edge(e) || cut[e]) {
        depth[f] = 0;
        queue.push(f);
        break;
      }
    }
  }
  if (queue.empty()) return 0;
  int last = queue.front();
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop();
    last = f;
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * f + c);
      if (t < 0 || cut[mesh.face_edge(f, c)] || depth[t / 3] >= 0) continue;
      depth[t / 3] = depth[f] + 1;
      queue.push(t / 3);
    }
  }
  return last;
}

// Corner of face f that holds vertex v.
int corner_of(const Triangulation& mesh, int f, int v) {
  for (int c = 0; c < 3; ++c) {
    if (mesh.face_vertex(f, c) == v) return c;
  }
  return -1;
}

}  // namespace

Complex DiskIsometry::operator()(Complex z) const {
  if (geometry == Geometry::Euclidean) return a * z + b;
  return (a * z + b) / (std::conj(b) * z + std::conj(a));
}

DiskIsometry DiskIsometry::operator*(const DiskIsometry& o) const {
  if (geometry == Geometry::Euclidean) return {geometry, a * o.a, a * o.b + b};
  return {geometry, a * o.a + b * std::conj(o.b), a * o.b + b * std::conj(o.a)};
}

DiskIsometry DiskIsometry::inverse() const {
  if (geometry == Geometry::Euclidean) return {geometry, 1.0 / a, -b / a};
  return {geometry, std::conj(a), -b};
}

DiskIsometry DiskIsometry::mapping(Geometry g, Complex p0, Complex p1, Complex q0, Complex q1) {
  if (g == Geometry::Euclidean) {
    const Complex rotation = std::polar(1.0, std::arg(q1 - q0) - std::arg(p1 - p0));
    return {g, rotation, q0 - rotation * p0};
  }
  const DiskIsometry from = move_to_origin(p0), to = move_to_origin(q0);
  const double phi = std::arg(to(q1)) - std::arg(from(p1));
  const DiskIsometry rotation{g, std::polar(1.0, phi / 2), 0.0};
  return to.inverse() * rotation * from;
}

ModelLayout develop(const Triangulation& mesh, Geometry geometry,
                    const std::vector<double>& lengths) {
  const int nf = mesh.num_faces();
  if (static_cast<int>(lengths.size()) != mesh.num_edges()) {
    throw InvalidArgumentError("layout: one length per edge is needed");
  }
  std::vector<TriangleAngles> angles(nf);
  for (int f = 0; f < nf; ++f) {
    angles[f] =
        corner_angles(geometry, {lengths[mesh.face_edge(f, 0)], lengths[mesh.face_edge(f, 1)],
                                 lengths[mesh.face_edge(f, 2)]});
    if (!angles[f].valid) {
      throw InvalidArgumentError("layout: face " + std::to_string(f) + " is not a valid " +
                                 to_string(geometry) + " triangle; lay out a converged metric");
    }
  }
  ModelLayout layout;
  layout.geometry = geometry;
  layout.cut = cut_to_disk(mesh);
  layout.corner.assign(nf, {});
  if (nf == 0) return layout;
  const int seed = deepest_face(mesh, layout.cut.cut);
  layout.seed_face = seed;

  // --- the seed face, then breadth-first across uncut edges
  const auto edge_length_at = [&](int f, int corner) { return lengths[mesh.face_edge(f, corner)]; };
  auto& p = layout.corner;
  if (geometry == Geometry::Spherical) {
    p[seed][0] = Eigen::Vector3d(0, 0, 1);
    const double l = edge_length_at(seed, 2);
    p[seed][1] = Eigen::Vector3d(std::sin(l), 0, std::cos(l));
  } else {
    const double l = edge_length_at(seed, 2);
    p[seed][0] = Eigen::Vector3d::Zero();
    p[seed][1] = Eigen::Vector3d(geometry == Geometry::Hyperbolic ? std::tanh(l / 2) : l, 0, 0);
  }
  p[seed][2] =
      place_third(geometry, p[seed][0], p[seed][1], edge_length_at(seed, 1), angles[seed].angle[0]);
  std::vector<char> placed(nf, 0);
  placed[seed] = 1;
  std::queue<int> queue;
  queue.push(seed);
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop();
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * f + c);
      if (t < 0 || layout.cut.cut[mesh.face_edge(f, c)] || placed[t / 3]) continue;
      const int g = t / 3, ct = t % 3, c1 = (ct + 1) % 3, c2 = (ct + 2) % 3;
      p[g][c1] = p[f][(c + 2) % 3];
      p[g][c2] = p[f][(c + 1) % 3];
      p[g][ct] =
          place_third(geometry, p[g][c1], p[g][c2], edge_length_at(g, c2), angles[g].angle[c1]);
      placed[g] = 1;
      queue.push(g);
    }
  }

  // --- deck transformations of the cut paths (E2, H2), and the closure error
  const bool planar = geometry != Geometry::Spherical;
  std::vector<int> path_of(mesh.num_edges(), -1), walked_from(mesh.num_edges(), -1);
  for (size_t k = 0; k < layout.cut.paths.size(); ++k) {
    const CutPath& path = layout.cut.paths[k];
    for (size_t i = 0; i < path.edges.size(); ++i) {
      path_of[path.edges[i]] = static_cast<int>(k);
      walked_from[path.edges[i]] = path.vertices[i];
    }
  }
  // Left and right faces of edge e walked from a to b.
  const auto sides = [&](int e, int a) {
    const int h = mesh.edge_halfedge(e), t = mesh.twin(h);
    return mesh.halfedge_tail(h) == a ? std::array<int, 2>{h / 3, t / 3}
                                      : std::array<int, 2>{t / 3, h / 3};
  };
  const auto at = [&](int f, int v) { return p[f][corner_of(mesh, f, v)]; };
  if (planar) {
    for (const CutPath& path : layout.cut.paths) {
      const int a = path.vertices[0], b = path.vertices[1];
      const auto [left, right] = sides(path.edges[0], a);
      layout.deck.push_back(DiskIsometry::mapping(geometry, to_complex(at(right, a)),
                                                  to_complex(at(right, b)), to_complex(at(left, a)),
                                                  to_complex(at(left, b))));
    }
  }
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (mesh.is_boundary_edge(e)) continue;
    const auto [a, b] = mesh.edge_vertices(e);
    if (!layout.cut.cut[e]) {
      const auto [f, g] = mesh.edge_faces(e);
      layout.closure_error = std::max(
          {layout.closure_error, (at(f, a) - at(g, a)).norm(), (at(f, b) - at(g, b)).norm()});
    } else if (planar) {
      const int from = walked_from[e];
      const int to = from == a ? b : a;
      const auto [left, right] = sides(e, from);
      const DiskIsometry& deck = layout.deck[path_of[e]];
      for (int v : {from, to}) {
        layout.closure_error =
            std::max(layout.closure_error,
                     std::abs(deck(to_complex(at(right, v))) - to_complex(at(left, v))));
      }
    }
  }
  for (int f = 0; f < nf; ++f) {
    if (!(orientation(geometry, p[f]) > 0)) ++layout.num_flipped_faces;
  }
  return layout;
}

std::vector<Eigen::Vector3d> vertex_positions(const Triangulation& mesh,
                                              const ModelLayout& layout) {
  std::vector<Eigen::Vector3d> position(mesh.num_vertices(), Eigen::Vector3d::Zero());
  std::vector<char> set(mesh.num_vertices(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.face_vertex(f, c);
      if (!set[v]) position[v] = layout.corner[f][c], set[v] = 1;
    }
  }
  return position;
}

std::vector<std::array<Eigen::Vector3d, 3>> corners_on(const Triangulation& laid_out,
                                                       const ModelLayout& layout,
                                                       const Triangulation& other) {
  std::map<std::array<int, 3>, int> face_of;  // sorted vertices -> face of laid_out
  std::vector<std::vector<Eigen::Vector3d>> wedges(laid_out.num_vertices());
  for (int f = 0; f < laid_out.num_faces(); ++f) {
    std::array<int, 3> key = laid_out.faces()[f];
    std::sort(key.begin(), key.end());
    face_of[key] = f;
    for (int c = 0; c < 3; ++c) wedges[laid_out.face_vertex(f, c)].push_back(layout.corner[f][c]);
  }
  std::vector<std::array<Eigen::Vector3d, 3>> corners(other.num_faces());
  for (int f = 0; f < other.num_faces(); ++f) {
    std::array<int, 3> key = other.faces()[f];
    std::sort(key.begin(), key.end());
    const auto same = face_of.find(key);
    for (int c = 0; c < 3; ++c) {
      const int v = other.face_vertex(f, c);
      if (same != face_of.end()) {
        corners[f][c] = layout.corner[same->second][corner_of(laid_out, same->second, v)];
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

double surface_group_relation_error(const Triangulation& mesh, const ModelLayout& layout) {
  if (layout.geometry == Geometry::Spherical || layout.deck.empty()) return 0;
  std::vector<int> path_of(mesh.num_edges(), -1), walked_from(mesh.num_edges(), -1);
  std::vector<int> cut_degree(mesh.num_vertices(), 0);
  for (size_t k = 0; k < layout.cut.paths.size(); ++k) {
    const CutPath& path = layout.cut.paths[k];
    for (size_t i = 0; i < path.edges.size(); ++i) {
      path_of[path.edges[i]] = static_cast<int>(k);
      walked_from[path.edges[i]] = path.vertices[i];
      for (int v : mesh.edge_vertices(path.edges[i])) ++cut_degree[v];
    }
  }
  double extent = 1;
  if (layout.geometry == Geometry::Euclidean) {
    extent = 0;
    for (const auto& face : layout.corner) {
      for (const auto& p : face) extent = std::max(extent, p.norm());
    }
    extent = std::max(extent, 1e-300);
  }
  // The face of interior vertex v's first corner, and v's corner there.
  std::vector<int> face_at(mesh.num_vertices(), -1);
  for (int f = mesh.num_faces() - 1; f >= 0; --f) {
    for (int c = 0; c < 3; ++c) face_at[mesh.face_vertex(f, c)] = f;
  }
  double error = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (cut_degree[v] < 3 || mesh.is_boundary_vertex(v)) continue;
    DiskIsometry product{layout.geometry, 1.0, 0.0};  // from the current face to the first
    const int first = face_at[v];
    int f = first;
    do {
      const int h = 3 * f + (corner_of(mesh, f, v) + 2) % 3;  // the halfedge leaving v
      const int e = mesh.face_edge(f, h % 3), g = mesh.twin(h) / 3;
      if (path_of[e] >= 0) {
        const auto& ends = mesh.edge_vertices(e);
        const int from = walked_from[e], to = from == ends[0] ? ends[1] : ends[0];
        // The path's left face holds the halfedge walked from `from` to `to`.
        const bool into_left =
            mesh.halfedge_tail(mesh.twin(h)) == from && mesh.halfedge_head(mesh.twin(h)) == to;
        const DiskIsometry& deck = layout.deck[path_of[e]];
        product = product * (into_left ? deck.inverse() : deck);
      }
      f = g;
    } while (f != first);
    const double a = layout.geometry == Geometry::Hyperbolic
                         ? std::min(std::abs(product.a - 1.0), std::abs(product.a + 1.0))
                         : std::abs(product.a - 1.0);
    error = std::max({error, a, std::abs(product.b) / extent});
  }
  return error;
}

std::vector<Eigen::Vector3d> center_on_sphere(std::vector<Eigen::Vector3d> points) {
  if (points.empty()) return points;
  // phi_a(x) = ((1 - |a|^2)(x - a) - |x - a|^2 a) / (1 - 2 a.x + |a|^2 |x|^2): the automorphism
  // of the unit ball that moves a to 0, a Moebius map of the sphere.
  const auto centroid = [&]() {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& x : points) c += x;
    return Eigen::Vector3d(c / static_cast<double>(points.size()));
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

}  // namespace ricci
