// The isometries of the models, and how a cut-open layout is glued back: deck transformations,
// the closure error and the surface group's relations.
#include <algorithm>
#include <cmath>

#include "layout/layout_methods.h"

namespace ricci {

using detail::corner_of;
using Complex = std::complex<double>;

namespace {

Complex to_complex(const Eigen::Vector3d& p) {
  return {p.x(), p.y()};
}

}  // namespace

DiskIsometry DiskIsometry::moving_to_origin(Complex p) {
  const double s = std::sqrt(1 - std::norm(p));
  return {Geometry::Hyperbolic, 1 / s, -p / s};
}

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
  const DiskIsometry from = moving_to_origin(p0), to = moving_to_origin(q0);
  const double phi = std::arg(to(q1)) - std::arg(from(p1));
  const DiskIsometry rotation{g, std::polar(1.0, phi / 2), 0.0};
  return to.inverse() * rotation * from;
}

void detail::glue_along_cut(const Triangulation& mesh, Layout& layout) {
  const Geometry geometry = layout.geometry;
  const bool planar = geometry != Geometry::Spherical;
  const auto& p = layout.corners;
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
  layout.deck.clear();
  layout.closure_error = 0;
  const bool charts = !layout.chart.empty();
  // Position of vertex v in face f, in the chart of face g: up the chart tree from f's chart to
  // the lowest common ancestor, then down to g's (charts that meet are near each other). The
  // transitions' entries grow like e^(d / 2) with the distance d between chart centres, and
  // composing them cancels most digits: in long double.
  using Wide = std::complex<long double>;
  struct WideMoebius {
    Wide a = 1, b = 0;
    WideMoebius operator*(const WideMoebius& o) const {
      return {a * o.a + b * std::conj(o.b), a * o.b + b * std::conj(o.a)};
    }
  };
  const auto wide = [](const DiskIsometry& m) { return WideMoebius{Wide(m.a), Wide(m.b)}; };
  const auto at_in_chart_of = [&](int f, int v, int g) -> Eigen::Vector3d {
    const Eigen::Vector3d x = at(f, v);
    if (!charts || layout.chart[f] == layout.chart[g]) return x;
    const auto depth = [&](int k) {
      int d = 0;
      for (; layout.chart_parent[k] >= 0; k = layout.chart_parent[k]) ++d;
      return d;
    };
    int from = layout.chart[f], to = layout.chart[g];
    WideMoebius up, down;  // from f's chart up to the ancestor's; from the ancestor's down to g's
    int df = depth(from), dt = depth(to);
    while (from != to) {
      if (df >= dt) {
        up = wide(layout.chart_from_parent[from].inverse()) * up;
        from = layout.chart_parent[from], --df;
      } else {
        down = down * wide(layout.chart_from_parent[to]);
        to = layout.chart_parent[to], --dt;
      }
    }
    const WideMoebius m = down * up;
    const Wide z(x.x(), x.y());
    const Wide moved = (m.a * z + m.b) / (std::conj(m.b) * z + std::conj(m.a));
    return {static_cast<double>(moved.real()), static_cast<double>(moved.imag()), 0};
  };
  if (planar && !charts) {
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
      for (int v : {a, b}) {
        const double gap = (at_in_chart_of(f, v, g) - at(g, v)).norm();
        if (std::isnan(gap) || std::isnan(layout.closure_error)) {
          layout.closure_error = std::nan("");
        } else {
          layout.closure_error = std::max(layout.closure_error, gap);
        }
      }
    } else if (planar && !charts) {
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
  layout.num_flipped_faces = 0;
  for (const auto& face : p) layout.num_flipped_faces += !(orientation(geometry, face) > 0);
}

double surface_group_relation_error(const Triangulation& mesh, const Layout& layout) {
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
    for (const auto& face : layout.corners) {
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
    double largest = 1;  // H2: the largest |a| of the partial products (rounding scales with it)
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
        largest = std::max(largest, std::abs(product.a));
      }
      f = g;
    } while (f != first);
    if (layout.geometry == Geometry::Hyperbolic) {
      const double a = std::min(std::abs(product.a - 1.0), std::abs(product.a + 1.0));
      error = std::max(error, std::max(a, std::abs(product.b)) / largest);
    } else {
      error = std::max({error, std::abs(product.a - 1.0), std::abs(product.b) / extent});
    }
  }
  return error;
}

}  // namespace ricci
