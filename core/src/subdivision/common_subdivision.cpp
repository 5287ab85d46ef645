#include "ricci/subdivision/common_subdivision.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include "layout/layout_methods.h"
#include "ricci/mesh/errors.h"
#include "subdivision/input_overlay.h"

namespace ricci {

namespace {

using detail::Crossing;
using detail::InputOverlay;

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
      const Eigen::Vector3d on_arc = detail::disk_geodesic_point(p, q, t);
      if (disk_points == DiskSidePoints::OnGeodesic) return on_arc;
      return detail::onto_drawn_side(p, q, on_arc);
    }
    default:
      return (1 - t) * p + t * q;
  }
}

// One face of the final triangulation cut by the input's edges into pieces.
struct FacePieces {
  struct Chord {
    int to;
    int input_edge;
    bool forward;  // from this point to `to` runs along the input edge's direction
  };
  std::vector<int> point_vertex;              // subdivision vertex of each boundary point
  std::vector<Eigen::Vector3d> point_layout;  // its layout position in this face
  std::vector<int> point_side;                // the side (corner it starts from) of the point
  std::vector<std::vector<Chord>> chords;     // per boundary point
};

}  // namespace

CommonSubdivision common_subdivision(const CompactMesh& mesh, const ConformalStructure& initial,
                                     const FlowResult& result, const Layout& layout,
                                     DiskSidePoints disk_points) {
  const auto begin = std::chrono::steady_clock::now();
  const Geometry g = layout.geometry;
  bool projective = true;
  for (const EdgeFlip& f : result.flip_sequence)
    projective = projective && (f.ptolemy || f.isometric);
  InputOverlay overlay(mesh, projective);
  for (const EdgeFlip& f : result.flip_sequence) overlay.flip(f);
  const Triangulation& T = overlay.triangulation();
  const Triangulation& flowed = result_triangulation(mesh, result);
  if (T.faces() != flowed.faces() || static_cast<int>(layout.corners.size()) != T.num_faces()) {
    throw LayoutError(
        "common subdivision: the replayed flips do not give the flow's triangulation");
  }
  const std::vector<Crossing>& crossings = overlay.crossings();
  const int nv = mesh.num_vertices();

  CommonSubdivision out;
  out.num_input_vertices = nv;
  out.num_flips = overlay.num_flips();
  out.positions = mesh.positions();
  out.u = Eigen::VectorXd(nv);
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

  // New vertices: input edge after input edge, along each.
  std::vector<int> vertex_of(crossings.size(), -1);
  std::vector<Eigen::VectorXd::Scalar> new_u;
  for (int E = 0; E < mesh.num_edges(); ++E) {
    const auto [a, b] = mesh.edge_vertices(E);
    for (int c = overlay.first_crossing(E); c >= 0; c = crossings[c].next) {
      const double s = realize(overlay, crossings[c].s, a, b, initial.u0);
      vertex_of[c] = static_cast<int>(out.positions.size());
      out.positions.push_back((1 - s) * mesh.positions()[a] + s * mesh.positions()[b]);
      out.vertex_input_edge.push_back(E);
      out.vertex_edge_parameter.push_back(s);
      const int f = mesh.edge_faces(E)[0];
      Eigen::Vector3d bary = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) {
        if (mesh.face_vertex(f, k) == a) bary[k] = 1 - s;
        if (mesh.face_vertex(f, k) == b) bary[k] = s;
      }
      out.vertex_input_face.push_back(f);
      out.vertex_barycentric.push_back(bary);
      new_u.push_back((1 - s) * result.u[a] + s * result.u[b]);
    }
  }
  out.u.conservativeResize(static_cast<long>(out.positions.size()));
  for (size_t i = 0; i < new_u.size(); ++i) out.u[nv + static_cast<long>(i)] = new_u[i];
  out.vertex_layout.assign(out.positions.size(), Eigen::Vector3d::Constant(std::nan("")));
  std::vector<char> laid(out.positions.size(), 0);

  // The input face to the left of input edge E walked forward (or backward).
  std::vector<int> point_of(crossings.size(), -1);  // a crossing's point in the face at hand
  auto face_left_of = [&](int E, bool forward) {
    const auto& ends = mesh.edge_vertices(E);
    const int tail = forward ? ends[0] : ends[1];
    const int h = mesh.edge_halfedge(E);
    if (mesh.halfedge_tail(h) == tail) return h / 3;
    const int t = mesh.twin(h);
    return t < 0 ? -1 : t / 3;
  };

  for (int face = 0; face < T.num_faces(); ++face) {
    auto fail = [&](const std::string& what) {
      throw LayoutError("common subdivision: face " + std::to_string(face) +
                        " of the final triangulation: " + what);
    };
    // Boundary points counter-clockwise: corner 0, its side's crossings, corner 1, ...
    FacePieces P;
    std::vector<int> index_of_crossing_here;  // parallel to `here`
    std::vector<int> here;                    // the crossings on this face's sides
    std::array<int, 3> corner_index{};
    for (int i = 0; i < 3; ++i) {
      const int v = T.face_vertex(face, i), w = T.face_vertex(face, (i + 1) % 3);
      corner_index[i] = static_cast<int>(P.point_vertex.size());
      P.point_vertex.push_back(v);
      P.point_layout.push_back(layout.corners[face][i]);
      P.point_side.push_back(i);
      const int edge = T.face_edge(face, (i + 2) % 3);
      std::vector<int> list = overlay.crossings_on(edge);
      if (T.edge_vertices(edge)[0] != v) std::reverse(list.begin(), list.end());
      for (int c : list) {
        const double t = overlay.t_from(c, v);
        const double tr = realize(overlay, t, v, w, result.u);
        here.push_back(c);
        index_of_crossing_here.push_back(static_cast<int>(P.point_vertex.size()));
        P.point_vertex.push_back(vertex_of[c]);
        P.point_layout.push_back(between(g, layout.corners[face][i],
                                         layout.corners[face][(i + 1) % 3], tr, disk_points));
        P.point_side.push_back(i);
      }
    }
    const int m = static_cast<int>(P.point_vertex.size());
    P.chords.assign(m, {});
    for (size_t i = 0; i < here.size(); ++i) point_of[here[i]] = index_of_crossing_here[i];
    auto index_of = [&](int crossing) { return point_of[crossing]; };
    auto corner_of_vertex = [&](int v) {
      for (int i = 0; i < 3; ++i) {
        if (T.face_vertex(face, i) == v) return corner_index[i];
      }
      return -1;
    };
    // On one closed side: points i and j both lie on side s = [corner s, corner s + 1].
    auto same_side = [&](int i, int j) {
      auto on_side = [&](int p, int s) {
        return P.point_side[p] == s || p == corner_index[(s + 1) % 3];
      };
      for (int s = 0; s < 3; ++s) {
        if (on_side(i, s) && on_side(j, s)) return true;
      }
      return false;
    };
    auto add_chord = [&](int from, int to, int E) {
      if (from < 0 || to < 0) fail("an input edge leaves it through no side");
      if (same_side(from, to)) fail("an input edge runs along one of its sides");
      P.chords[from].push_back({to, E, true});
      P.chords[to].push_back({from, E, false});
    };
    for (size_t i = 0; i < here.size(); ++i) {
      const Crossing& x = crossings[here[i]];
      const auto& faces = T.edge_faces(x.edge);
      const int from = x.forward ? faces[0] : faces[1], to = x.forward ? faces[1] : faces[0];
      const int E = x.input_edge;
      if (from == face) {
        const int before =
            x.prev >= 0 ? index_of(x.prev) : corner_of_vertex(mesh.edge_vertices(E)[0]);
        add_chord(before, index_of_crossing_here[i], E);
      }
      if (to == face && x.next < 0) {
        add_chord(index_of_crossing_here[i], corner_of_vertex(mesh.edge_vertices(E)[1]), E);
      }
    }
    for (int c : here) point_of[c] = -1;
    // The pieces: walk each region keeping it on the left, from every unused boundary arc.
    std::vector<char> arc_used(m, 0);
    for (int start = 0; start < m; ++start) {
      if (arc_used[start]) continue;
      std::vector<int> polygon = {start};
      int input_face = -1;
      auto note_step = [&](int E, bool forward) {
        const int f = face_left_of(E, forward);
        if (f < 0 || (input_face >= 0 && input_face != f)) {
          fail("a piece lies in two input faces");
        }
        input_face = f;
      };
      // A boundary arc from point p to p + 1 along a side that is an input edge.
      auto arc_step = [&](int p) {
        const int side = P.point_side[p];
        const int edge = T.face_edge(face, (side + 2) % 3);
        const int E = overlay.coincident_input_edge(edge);
        if (E < 0) return;
        const int v = T.face_vertex(face, side);
        note_step(E, mesh.edge_vertices(E)[0] == v);
      };
      arc_used[start] = 1;
      arc_step(start);
      int prev = start, cur = (start + 1) % m;
      for (int steps = 0; cur != start; ++steps) {
        if (steps > 2 * m + 8) fail("a piece does not close");
        polygon.push_back(cur);
        // Next: the neighbour with the largest counter-clockwise offset below the previous one's.
        const int back = (prev - cur + m) % m;
        int best = (cur + 1) % m, best_offset = 1;
        const FacePieces::Chord* via = nullptr;
        for (const auto& ch : P.chords[cur]) {
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
      if (polygon.size() < 3) fail("a piece with fewer than three corners");
      if (input_face < 0) fail("a piece touches no input edge");
      for (size_t i = 1; i + 1 < polygon.size(); ++i) {
        const std::array<int, 3> corner = {polygon[0], polygon[i], polygon[i + 1]};
        std::array<int, 3> tri{};
        std::array<Eigen::Vector3d, 3> pos;
        for (int k = 0; k < 3; ++k) {
          tri[k] = P.point_vertex[corner[k]];
          pos[k] = P.point_layout[corner[k]];
          if (!laid[tri[k]]) {
            laid[tri[k]] = 1;
            out.vertex_layout[tri[k]] = pos[k];
          }
        }
        out.faces.push_back(tri);
        out.corners.push_back(pos);
        out.input_face.push_back(input_face);
        out.final_face.push_back(face);
      }
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return out;
}

}  // namespace ricci
