#include "pipeline/disk_drawing.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <unordered_map>
#include <utility>

#include "layout/layout_methods.h"
#include "ricci/layout/layout.h"
#include "ricci/pipeline/layout_quality.h"

namespace ricci::detail {

namespace {

std::array<Eigen::Vector3d, 3> klein(const std::array<Eigen::Vector3d, 3>& poincare) {
  std::array<Eigen::Vector3d, 3> k;
  for (int c = 0; c < 3; ++c) k[c] = 2 * poincare[c] / (1 + poincare[c].squaredNorm());
  return k;
}

// Turned over as drawn (beyond what rounding decides), positive as a hyperbolic triangle.
bool turned_only_as_drawn(const std::array<Eigen::Vector3d, 3>& corners) {
  return !(orientation(Geometry::Hyperbolic, corners) > 0) &&
         orientation(Geometry::Hyperbolic, klein(corners)) > 0 && !orientation_unresolved(corners);
}

int corner_of_vertex(const CompactMesh& mesh, int f, int v) {
  for (int c = 0; c < 3; ++c) {
    if (mesh.face_vertex(f, c) == v) return c;
  }
  return -1;
}

// Where a delivered vertex lies in terms of the input: on input edge `edge` at parameter s (from
// the edge's first vertex), or (edge < 0) inside an input face.
struct EdgePoint {
  int edge = -1;
  double s = 0;
};

Eigen::Vector3d lift(std::complex<double> z) {  // onto the hyperboloid w^2 - x^2 - y^2 = 1
  const double r2 = std::norm(z);
  return Eigen::Vector3d(2 * z.real(), 2 * z.imag(), 1 + r2) / (1 - r2);
}

double minkowski(const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
  return x[0] * y[0] + x[1] * y[1] - x[2] * y[2];
}

// The hyperboloid weight toward q of the foot of the perpendicular from r onto the geodesic from p
// to q, in [0.05, 0.95] (computed with p moved to the disk's centre).
double foot_weight(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  const DiskIsometry m = DiskIsometry::moving_to_origin({p.x(), p.y()});
  const Eigen::Vector3d A(0, 0, 1), B = lift(m({q.x(), q.y()})), C = lift(m({r.x(), r.y()}));
  Eigen::Matrix2d gram;
  gram << minkowski(A, A), minkowski(A, B), minkowski(A, B), minkowski(B, B);
  const Eigen::Vector2d x =
      gram.fullPivLu().solve(Eigen::Vector2d(minkowski(C, A), minkowski(C, B)));
  const double w = x[1] / (x[0] + x[1]);
  return std::isfinite(w) ? std::clamp(w, 0.05, 0.95) : 0.5;
}

// The fraction of the geodesic's length from p to the point of hyperboloid weight w toward q.
double length_fraction(const Eigen::Vector3d& p, const Eigen::Vector3d& q, double w) {
  const DiskIsometry m = DiskIsometry::moving_to_origin({p.x(), p.y()});
  const Eigen::Vector3d point = disk_geodesic_point(p, q, w);
  const std::complex<double> at = m({point.x(), point.y()});
  const double whole = std::atanh(std::abs(m({q.x(), q.y()})));
  const double t = std::atanh(std::abs(at)) / whole;
  return std::isfinite(whole) && whole > 0 && std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.5;
}

// The hyperboloid weight toward q of the point at fraction t of the geodesic's length from p to q
// (the inverse of length_fraction): sinh(t d) against sinh((1 - t) d), d the geodesic's length.
double weight_at_length_fraction(const Eigen::Vector3d& p, const Eigen::Vector3d& q, double t) {
  const double d =
      2 * std::asinh((p - q).norm() / std::sqrt((1 - p.squaredNorm()) * (1 - q.squaredNorm())));
  if (!(d > 1e-12) || !std::isfinite(d)) return t;
  const double near = std::sinh((1 - t) * d), far = std::sinh(t * d);
  return far / (near + far);
}

class Splitter {
 public:
  Splitter(const CompactMesh& mesh, CommonSubdivision& sub) : mesh_(mesh), sub_(sub) {}

  // Barycentric coordinates of delivered vertex v in input face f, which holds it.
  Eigen::Vector3d barycentric(int f, int v) const {
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    if (v < sub_.num_input_vertices) {
      const int c = corner_of_vertex(mesh_, f, v);
      if (c >= 0) {
        b[c] = 1;
        return b;
      }
    } else {
      const EdgePoint p = on_edge(v);
      if (p.edge >= 0) {
        const auto [e0, e1] = mesh_.edge_vertices(p.edge);
        const int c0 = corner_of_vertex(mesh_, f, e0), c1 = corner_of_vertex(mesh_, f, e1);
        if (c0 >= 0 && c1 >= 0) {
          b[c0] = 1 - p.s;
          b[c1] = p.s;
          return b;
        }
      } else if (sub_.vertex_input_face[v] == f) {
        return sub_.vertex_barycentric[v];
      }
    }
    // Not expected: least squares in the face's plane.
    const Eigen::Vector3d a = mesh_.positions()[mesh_.face_vertex(f, 0)];
    Eigen::Matrix<double, 3, 2> m;
    m.col(0) = mesh_.positions()[mesh_.face_vertex(f, 1)] - a;
    m.col(1) = mesh_.positions()[mesh_.face_vertex(f, 2)] - a;
    const Eigen::Vector2d st = m.colPivHouseholderQr().solve(sub_.positions[v] - a);
    return {1 - st[0] - st[1], st[0], st[1]};
  }

  EdgePoint on_edge(int v) const {
    if (v < sub_.num_input_vertices) return {};
    const size_t i = static_cast<size_t>(v - sub_.num_input_vertices);
    return {sub_.vertex_input_edge[i], sub_.vertex_edge_parameter[i]};
  }

  // The input edge holding both a and b (a side of input face f), with the parameter there of the
  // point dividing a-b at fraction t; or edge -1.
  EdgePoint common_edge(int f, int a, int b, double t) const {
    auto parameter_on = [&](int e, int v) {
      const auto& ends = mesh_.edge_vertices(e);
      if (v == ends[0]) return 0.0;
      if (v == ends[1]) return 1.0;
      const EdgePoint p = on_edge(v);
      return p.edge == e ? p.s : std::nan("");
    };
    for (int c = 0; c < 3; ++c) {
      const int e = mesh_.face_edge(f, c);
      const double sa = parameter_on(e, a), sb = parameter_on(e, b);
      if (!std::isnan(sa) && !std::isnan(sb)) return {e, (1 - t) * sa + t * sb};
    }
    return {};
  }

  // Splits the side from corner c to corner c + 1 of every face in `faces` (all on one side) at the
  // point of the geodesic with hyperboloid weight w toward the second end of faces[0]'s side
  // (isometries act linearly on the hyperboloid: the weight names one point of the surface in
  // every copy of the side). In 3D the new vertex divides the side as it divides the geodesic.
  void split(const std::vector<std::pair<int, int>>& faces, double w) {
    const auto [f0, c0] = faces.front();
    const int a = sub_.faces[f0][c0], b = sub_.faces[f0][(c0 + 1) % 3];
    const int input = sub_.input_face[f0];
    const int m = static_cast<int>(sub_.positions.size());
    const double t = length_fraction(sub_.corners[f0][c0], sub_.corners[f0][(c0 + 1) % 3], w);
    EdgePoint along = common_edge(input, a, b, t);
    if (along.edge >= 0) {
      const auto [e0, e1] = mesh_.edge_vertices(along.edge);
      sub_.positions.push_back((1 - along.s) * mesh_.positions()[e0] +
                               along.s * mesh_.positions()[e1]);
      sub_.vertex_input_face.push_back(input);
      sub_.vertex_barycentric.push_back(Eigen::Vector3d::Zero());
      sub_.vertex_barycentric.back()[corner_of_vertex(mesh_, input, e0)] = 1 - along.s;
      sub_.vertex_barycentric.back()[corner_of_vertex(mesh_, input, e1)] = along.s;
    } else {
      sub_.positions.push_back((1 - t) * sub_.positions[a] + t * sub_.positions[b]);
      sub_.vertex_input_face.push_back(input);
      sub_.vertex_barycentric.push_back((1 - t) * barycentric(input, a) +
                                        t * barycentric(input, b));
    }
    sub_.vertex_input_edge.push_back(along.edge);
    sub_.vertex_edge_parameter.push_back(along.edge >= 0 ? along.s : std::nan(""));
    sub_.u.conservativeResize(m + 1);
    sub_.u[m] = (1 - t) * sub_.u[a] + t * sub_.u[b];
    sub_.vertex_layout.push_back(Eigen::Vector3d::Constant(std::nan("")));
    const bool model = !sub_.model_corners.empty();
    for (const auto& [f, c] : faces) {
      const std::array<int, 3> v = sub_.faces[f];
      const std::array<Eigen::Vector3d, 3> p = sub_.corners[f];
      const int d = (c + 1) % 3, o = (c + 2) % 3;
      const Eigen::Vector3d at = disk_geodesic_point(p[c], p[d], v[c] == a ? w : 1 - w);
      if (f == f0) sub_.vertex_layout[m] = at;
      sub_.faces[f] = {v[c], m, v[o]};
      sub_.corners[f] = {p[c], at, p[o]};
      sub_.faces.push_back({m, v[d], v[o]});
      sub_.corners.push_back({at, p[d], p[o]});
      sub_.input_face.push_back(sub_.input_face[f]);
      sub_.final_face.push_back(sub_.final_face[f]);
      if (!sub_.chart.empty()) sub_.chart.push_back(sub_.chart[f]);
      if (model) {
        // On the model's geodesic at the fraction of its length at which the vertex divides the
        // side in 3D: the copies of a side across a cut are isometric there, so the new vertex's
        // copies are images of each other under the deck transformation.
        const std::array<Eigen::Vector3d, 3> q = sub_.model_corners[f];
        const double fraction = v[c] == a ? t : 1 - t;
        const Eigen::Vector3d on_model =
            disk_geodesic_point(q[c], q[d], weight_at_length_fraction(q[c], q[d], fraction));
        sub_.model_corners[f] = {q[c], on_model, q[o]};
        sub_.model_corners.push_back({on_model, q[d], q[o]});
      }
    }
  }

 private:
  const CompactMesh& mesh_;
  CommonSubdivision& sub_;
};

// Where to split the side from corner c to c + 1 of `faces` (faces[0] the one to mend): the
// hyperboloid weight toward faces[0]'s second end. The midpoint when every half on the side is
// then drawn positive, else the foot of the perpendicular from faces[0]'s third corner when that
// makes them positive, else whichever leaves fewer halves turned.
double split_weight(const CommonSubdivision& sub, const std::vector<std::pair<int, int>>& faces) {
  const auto [f0, c0] = faces.front();
  const auto& p0 = sub.corners[f0];
  const int a = sub.faces[f0][c0];
  const double foot = foot_weight(p0[c0], p0[(c0 + 1) % 3], p0[(c0 + 2) % 3]);
  const auto turned_halves = [&](double w) {
    int n = 0;
    for (const auto& [f, c] : faces) {
      const auto& p = sub.corners[f];
      const Eigen::Vector3d &from = p[c], &to = p[(c + 1) % 3], &third = p[(c + 2) % 3];
      const Eigen::Vector3d at = disk_geodesic_point(from, to, sub.faces[f][c] == a ? w : 1 - w);
      for (const std::array<Eigen::Vector3d, 3>& half :
           {std::array<Eigen::Vector3d, 3>{from, at, third}, {at, to, third}}) {
        n += !(orientation(Geometry::Hyperbolic, half) > 0) && !orientation_unresolved(half);
      }
    }
    return n;
  };
  const int at_middle = turned_halves(0.5);
  if (at_middle == 0) return 0.5;
  return turned_halves(foot) < at_middle ? foot : 0.5;
}

}  // namespace

CommonSubdivision input_as_subdivision(const CompactMesh& mesh, const FlowResult& result,
                                       const std::vector<std::array<Eigen::Vector3d, 3>>& corners) {
  CommonSubdivision sub;
  const int nv = mesh.num_vertices();
  sub.num_input_vertices = nv;
  sub.positions = mesh.positions();
  sub.faces = mesh.faces();
  sub.corners = corners;
  sub.u = result.u.head(nv);
  sub.vertex_input_face.assign(nv, -1);
  sub.vertex_barycentric.assign(nv, Eigen::Vector3d::Zero());
  sub.vertex_layout.assign(nv, Eigen::Vector3d::Constant(std::nan("")));
  for (int f = 0; f < mesh.num_faces(); ++f) {
    sub.input_face.push_back(f);
    sub.final_face.push_back(f);
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.face_vertex(f, c);
      if (sub.vertex_input_face[v] >= 0) continue;
      sub.vertex_input_face[v] = f;
      sub.vertex_barycentric[v][c] = 1;
      sub.vertex_layout[v] = corners[f][c];
    }
  }
  return sub;
}

bool has_drawing_turned_faces(const std::vector<std::array<Eigen::Vector3d, 3>>& corners) {
  for (const auto& p : corners) {
    if (turned_only_as_drawn(p)) return true;
  }
  return false;
}

std::vector<char> final_faces_turned_as_drawn(const CommonSubdivision& sub, int num_final_faces) {
  std::vector<char> turned(static_cast<size_t>(num_final_faces), 0);
  for (size_t f = 0; f < sub.faces.size(); ++f) {
    if (turned_only_as_drawn(sub.corners[f])) turned[static_cast<size_t>(sub.final_face[f])] = 1;
  }
  return turned;
}

int draw_sides_straight(CommonSubdivision& sub, const Layout& layout,
                        const std::vector<char>& final_faces) {
  const int n = sub.num_input_vertices;
  if (sub.model_corners.empty()) sub.model_corners = sub.corners;
  std::vector<char> moved(sub.positions.size(), 0);
  for (size_t f = 0; f < sub.faces.size(); ++f) {
    if (!final_faces[static_cast<size_t>(sub.final_face[f])]) continue;
    for (int v : sub.faces[f]) moved[static_cast<size_t>(v)] = v >= n;
  }
  const auto to_klein = [](const Eigen::Vector3d& z) {
    return Eigen::Vector2d(z.head<2>() * 2 / (1 + z.squaredNorm()));
  };
  int count = 0;
  for (size_t f = 0; f < sub.faces.size(); ++f) {
    const auto& frame = layout.corners[static_cast<size_t>(sub.final_face[f])];
    for (int c = 0; c < 3; ++c) {
      if (!moved[static_cast<size_t>(sub.faces[f][c])]) continue;
      // The side whose geodesic holds the point: straight through it in the Klein model.
      const Eigen::Vector2d k = to_klein(sub.corners[f][c]);
      int side = 0;
      double best = INFINITY;
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector2d a = to_klein(frame[i]), d = to_klein(frame[(i + 1) % 3]) - a;
        const double off = std::abs(d.x() * (k - a).y() - d.y() * (k - a).x()) / d.norm();
        if (off < best) best = off, side = i;
      }
      sub.corners[f][c] = onto_drawn_side(frame[side], frame[(side + 1) % 3], sub.corners[f][c]);
      ++count;
    }
  }
  return count;
}

int split_turned_disk_faces(const CompactMesh& mesh, CommonSubdivision& sub, int max_rounds) {
  const auto to_mend = [&] {
    int n = 0;
    for (const auto& p : sub.corners) n += turned_only_as_drawn(p);
    return n;
  };
  // A split can turn a neighbour over for a round: the best state seen (fewest faces to mend, then
  // fewest splits) is kept, and the rounds stop after 20 without progress or when the faces to
  // mend grow far past their first number.
  const int first = to_mend();
  int splits = 0, turned = first, best = first, best_splits = 0, since_best = 0;
  CommonSubdivision best_state;
  for (int round = 0;
       round < max_rounds && turned > 0 && since_best < 20 && turned <= 4 * first + 16; ++round) {
    if (turned < best || round == 0) {
      best = turned, best_splits = splits, since_best = 0;
      best_state = sub;
    }
    const int nf = static_cast<int>(sub.faces.size());
    const auto key = [&](int a, int b) {
      return static_cast<long long>(std::min(a, b)) * static_cast<long long>(sub.positions.size()) +
             std::max(a, b);
    };
    // Per face to mend: its longest drawn side (where on it: split_weight).
    std::vector<std::pair<long long, int>> chosen;
    for (int f = 0; f < nf; ++f) {
      if (!turned_only_as_drawn(sub.corners[f])) continue;
      int longest = 0;
      for (int c = 1; c < 3; ++c) {
        if ((sub.corners[f][(c + 1) % 3] - sub.corners[f][c]).norm() >
            (sub.corners[f][(longest + 1) % 3] - sub.corners[f][longest]).norm()) {
          longest = c;
        }
      }
      chosen.emplace_back(key(sub.faces[f][longest], sub.faces[f][(longest + 1) % 3]), f);
    }
    if (chosen.empty()) break;
    // The chosen sides' faces, by the sides' ends: (face, corner the side starts at).
    std::unordered_map<long long, std::vector<std::pair<int, int>>> sides;
    for (const auto& [k, trigger] : chosen) sides[k];
    for (int f = 0; f < nf; ++f) {
      for (int c = 0; c < 3; ++c) {
        const auto side = sides.find(key(sub.faces[f][c], sub.faces[f][(c + 1) % 3]));
        if (side != sides.end()) side->second.emplace_back(f, c);
      }
    }
    int split_here = 0;
    std::vector<char> touched(nf, 0);
    for (const auto& [k, trigger] : chosen) {
      std::vector<std::pair<int, int>>& faces = sides[k];
      if (faces.size() == 2 && faces[1].first == trigger) std::swap(faces[0], faces[1]);
      // One side: in one face, or in two that run it in opposite directions (two sides with the
      // same ends would be pinched into one vertex).
      bool one_side = faces.size() == 1;
      if (faces.size() == 2) {
        const auto& [f, c] = faces[0];
        const auto& [g, d] = faces[1];
        one_side = sub.faces[f][c] == sub.faces[g][(d + 1) % 3];
      }
      bool free = one_side;
      for (const auto& fc : faces) free = free && !touched[fc.first];
      if (!free) continue;
      for (const auto& fc : faces) touched[fc.first] = 1;
      Splitter(mesh, sub).split(faces, split_weight(sub, faces));
      ++split_here;
    }
    if (split_here == 0) break;
    splits += split_here;
    turned = to_mend();
    since_best = turned < best ? 0 : since_best + 1;
  }
  if (turned > best || (turned == best && splits > best_splits)) {
    sub = std::move(best_state);
    splits = best_splits;
  }
  return splits;
}

}  // namespace ricci::detail
