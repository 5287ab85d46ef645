#include "subdivision/face_pieces.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "layout/layout_methods.h"
#include "ricci/mesh/errors.h"
#include "ricci/mesh/geometry.h"

namespace ricci::detail {

// The input's vertices as the subdivision's first ones: their positions, u (room for `extra`
// new vertices' u after them), and each one's first input face with a unit coordinate there.
void place_input_vertices(const CompactMesh& mesh, const FlowResult& result, int extra,
                          CommonSubdivision& out) {
  const int nv = mesh.num_vertices();
  out.positions = mesh.positions();
  out.u = Eigen::VectorXd(nv + extra);
  for (int v = 0; v < nv; ++v) out.u[v] = result.u[v];
  out.vertex_input_face.assign(nv, -1);
  out.vertex_barycentric.assign(nv, Eigen::Vector3d::Zero());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.face_vertex(f, c);
      if (out.vertex_input_face[v] >= 0) continue;
      out.vertex_input_face[v] = f;
      out.vertex_barycentric[v][c] = 1;
    }
  }
}

// Barycentric coordinates (1 - t, t) of a point on edge (v0, v1), from the overlay's convention
// to the realization of the metric with conformal factor u.
double realize(const InputOverlay& overlay, double t, int v0, int v1, const Eigen::VectorXd& u) {
  if (!overlay.projective()) return t;
  const double w0 = (1 - t) * std::exp(-(u[v0] - u[v1]) / 2),
               w1 = t * std::exp((u[v0] - u[v1]) / 2);
  return w1 / (w0 + w1);
}

// The point with barycentric coordinates (1 - t, t) between two corners of a laid-out triangle
// of the final metric: straight in the plane, the chord's central projection on the sphere, and
// through the hyperboloid for the Poincare disk.
Eigen::Vector3d between(Geometry g, const Eigen::Vector3d& p, const Eigen::Vector3d& q, double t,
                        DiskSidePoints disk_points) {
  switch (g) {
    case Geometry::Spherical:
      return ((1 - t) * p + t * q).normalized();
    case Geometry::Hyperbolic: {
      const Eigen::Vector3d on_arc = disk_geodesic_point(p, q, t);
      if (disk_points == DiskSidePoints::OnGeodesic) return on_arc;
      return onto_drawn_side(p, q, on_arc);
    }
    default:
      return (1 - t) * p + t * q;
  }
}

namespace {

// The input face to the left of input edge E walked forward (or backward); -1 beyond the boundary.
int face_left_of(const Triangulation& input, int E, bool forward) {
  const auto& ends = input.edge_vertices(E);
  const int tail = forward ? ends[0] : ends[1];
  const int h = input.edge_halfedge(E);
  if (input.halfedge_tail(h) == tail) return h / 3;
  const int t = input.twin(h);
  return t < 0 ? -1 : t / 3;
}

}  // namespace

// Cuts face `face` of the overlay's current triangulation by the input's edges.
FaceCut cut_face(const InputOverlay& overlay, int face) {
  const Triangulation& T = overlay.triangulation();
  const Triangulation& input = overlay.input();
  const std::vector<Crossing>& crossings = overlay.crossings();
  auto fail = [&](const std::string& what) {
    throw LayoutError("common subdivision: face " + std::to_string(face) +
                      " of the final triangulation: " + what);
  };
  struct Chord {
    int to;
    int input_edge;
    bool forward;  // from this point to `to` runs along the input edge's direction
  };
  FaceCut out;
  std::vector<BoundaryPoint>& points = out.points;
  points.reserve(8);
  std::array<int, 3> corner_index{};
  for (int i = 0; i < 3; ++i) {
    corner_index[i] = static_cast<int>(points.size());
    points.push_back({i, -1, i});
    std::vector<int> list = overlay.crossings_on(T.face_edge(face, (i + 2) % 3));
    if (!overlay.runs_from_tail(InputOverlay::side_halfedge(face, i)))
      std::reverse(list.begin(), list.end());
    for (int c : list) points.push_back({-1, c, i});
  }
  const int m = static_cast<int>(points.size());
  std::vector<std::vector<Chord>> chords(m);
  std::unordered_map<int, int> point_of_crossing;
  for (int p = 0; p < m; ++p) {
    if (points[p].crossing >= 0) point_of_crossing[points[p].crossing] = p;
  }
  auto index_of = [&](int crossing) {
    const auto it = point_of_crossing.find(crossing);
    return it == point_of_crossing.end() ? -1 : it->second;
  };
  // The corner at vertex v from which an input edge runs straight to the crossing at point p: the
  // corner opposite p's side (the face may have two corners at v, on either side of a loop).
  auto corner_to = [&](int v, int p) {
    const int opposite = (points[p].side + 2) % 3;
    return T.face_vertex(face, opposite) == v ? corner_index[opposite] : -1;
  };
  // On one closed side: points i and j both lie on side s = [corner s, corner s + 1].
  auto same_side = [&](int i, int j) {
    auto on_side = [&](int p, int s) {
      return points[p].side == s || p == corner_index[(s + 1) % 3];
    };
    for (int s = 0; s < 3; ++s) {
      if (on_side(i, s) && on_side(j, s)) return true;
    }
    return false;
  };
  auto add_chord = [&](int from, int to, int E) {
    if (from < 0 || to < 0) fail("an input edge leaves it through no side");
    if (same_side(from, to)) fail("an input edge runs along one of its sides");
    chords[from].push_back({to, E, true});
    chords[to].push_back({from, E, false});
  };
  for (int p = 0; p < m; ++p) {
    if (points[p].crossing < 0) continue;
    const Crossing& x = crossings[points[p].crossing];
    const auto& faces = T.edge_faces(x.edge);
    const int from = x.forward ? faces[0] : faces[1], to = x.forward ? faces[1] : faces[0];
    const int E = x.input_edge;
    if (from == face) {
      const int before = x.prev >= 0 ? index_of(x.prev) : corner_to(input.edge_vertices(E)[0], p);
      add_chord(before, p, E);
    }
    if (to == face && x.next < 0) add_chord(p, corner_to(input.edge_vertices(E)[1], p), E);
  }
  // The pieces: walk each region keeping it on the left, from every unused boundary arc.
  std::vector<char> arc_used(m, 0);
  for (int start = 0; start < m; ++start) {
    if (arc_used[start]) continue;
    FacePiece piece;
    const int most = std::min(m, 8);  // most pieces have few points: not m each (the cheese's m
    piece.points.reserve(most);       // are hundreds)
    piece.along.reserve(most);
    piece.arc.reserve(most);
    piece.points.push_back(start);
    auto note_step = [&](int E, bool forward) {
      const int f = face_left_of(input, E, forward);
      if (f < 0 || (piece.input_face >= 0 && piece.input_face != f)) {
        fail("a piece lies in two input faces");
      }
      piece.input_face = f;
      piece.along.push_back(E);
      piece.arc.push_back(0);
    };
    // A boundary arc from point p to p + 1 along a side that is an input edge.
    auto arc_step = [&](int p) {
      const int side = points[p].side;
      const int E = overlay.coincident_input_edge(T.face_edge(face, (side + 2) % 3));
      if (E < 0) {
        piece.along.push_back(-1);
        piece.arc.push_back(0);
      } else {
        note_step(E, input.edge_vertices(E)[0] == T.face_vertex(face, side));
      }
      piece.arc.back() = 1;
    };
    arc_used[start] = 1;
    arc_step(start);
    int prev = start, cur = (start + 1) % m;
    for (int steps = 0; cur != start; ++steps) {
      if (steps > 2 * m + 8) fail("a piece does not close");
      piece.points.push_back(cur);
      // Next: the neighbour with the largest counter-clockwise offset below the previous one's.
      const int back = (prev - cur + m) % m;
      int best = (cur + 1) % m, best_offset = 1;
      const Chord* via = nullptr;
      for (const auto& ch : chords[cur]) {
        const int off = (ch.to - cur + m) % m;
        if (off < back && off > best_offset) best = ch.to, best_offset = off, via = &ch;
      }
      if (via) {
        note_step(via->input_edge, via->forward);
      } else {
        if (arc_used[cur]) fail("a boundary arc is walked twice");
        arc_used[cur] = 1;
        arc_step(cur);
      }
      prev = cur;
      cur = best;
    }
    if (piece.points.size() < 3) fail("a piece with fewer than three corners");
    if (piece.input_face < 0) fail("a piece touches no input edge");
    out.pieces.push_back(std::move(piece));
  }
  return out;
}

}  // namespace ricci::detail
