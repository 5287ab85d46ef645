#include "ricci/subdivision/common_subdivision.h"

#include <cmath>
#include <vector>

#include "mesh/clock.h"
#include "ricci/mesh/errors.h"
#include "subdivision/face_pieces.h"
#include "subdivision/input_overlay.h"
#include "subdivision/piece_triangles.h"
#include "subdivision/through_delaunay.h"

namespace ricci {

using detail::between;
using detail::BoundaryPoint;
using detail::Crossing;
using detail::cut_face;
using detail::FaceCut;
using detail::FacePiece;
using detail::InputOverlay;
using detail::place_input_vertices;
using detail::realize;

CommonSubdivision common_subdivision(const CompactMesh& mesh, const ConformalStructure& initial,
                                     const FlowResult& result, const Layout& layout,
                                     DiskSidePoints disk_points, PieceTriangles how) {
  const auto begin = detail::Clock::now();
  const Geometry g = layout.geometry;
  bool projective = true;
  for (const EdgeFlip& f : result.flip_sequence)
    projective = projective && (f.ptolemy || f.isometric);
  // The isometric flips come first (make_input_delaunay), then the flow's.
  size_t split = 0;
  while (split < result.flip_sequence.size() && result.flip_sequence[split].isometric) ++split;
  bool isometric_later = false;
  for (size_t i = split; i < result.flip_sequence.size(); ++i)
    isometric_later = isometric_later || result.flip_sequence[i].isometric;
  if (projective && split > 0 && !isometric_later && g != Geometry::Hyperbolic) {
    CommonSubdivision out =
        detail::subdivision_through_delaunay(mesh, initial, result, layout, split, how);
    out.seconds = detail::seconds_since(begin);
    return out;
  }
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
  place_input_vertices(mesh, result, 0, out);

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

  for (int face = 0; face < T.num_faces(); ++face) {
    const FaceCut cut = cut_face(overlay, face);
    for (const FacePiece& piece : cut.pieces) {
      auto vertex_of_point = [&](int p) {
        const BoundaryPoint& b = cut.points[p];
        return b.corner >= 0 ? T.face_vertex(face, b.corner) : vertex_of[b.crossing];
      };
      auto layout_of_point = [&](int p) -> Eigen::Vector3d {
        const BoundaryPoint& b = cut.points[p];
        if (b.corner >= 0) return layout.corners[face][b.corner];
        const int v = T.face_vertex(face, b.side), w = T.face_vertex(face, (b.side + 1) % 3);
        const double tr =
            realize(overlay, overlay.t_on_side(b.crossing, face, b.side), v, w, result.u);
        return between(g, layout.corners[face][b.side], layout.corners[face][(b.side + 1) % 3], tr,
                       disk_points);
      };
      const std::vector<int>& polygon = piece.points;
      // The Poincare disk's pieces are drawn again later, in charts and on their straight sides,
      // where other diagonals than a fan's could turn over: they keep the fan, and so do the
      // sphere's on this route (its layout has no plane to measure them in).
      std::vector<std::array<size_t, 3>> triangles;
      if (g == Geometry::Euclidean) {  // the piece in its input face's plane, and in the layout
        const Eigen::Vector3d a = mesh.positions()[mesh.face_vertex(piece.input_face, 0)],
                              b = mesh.positions()[mesh.face_vertex(piece.input_face, 1)],
                              c = mesh.positions()[mesh.face_vertex(piece.input_face, 2)];
        const Eigen::Vector3d e1 = (b - a).normalized(),
                              e2 = (b - a).cross(c - a).normalized().cross(e1);
        std::vector<Eigen::Vector2d> domain, image;
        for (int p : polygon) {
          const Eigen::Vector3d d = out.positions[vertex_of_point(p)] - a;
          domain.emplace_back(d.dot(e1), d.dot(e2));
          image.push_back(layout_of_point(p).head<2>());
        }
        triangles = detail::piece_triangles(domain, image, how);
      } else {
        for (size_t i = 1; i + 1 < polygon.size(); ++i) triangles.push_back({0, i, i + 1});
      }
      for (const std::array<size_t, 3>& t : triangles) {
        const std::array<int, 3> corner = {polygon[t[0]], polygon[t[1]], polygon[t[2]]};
        std::array<int, 3> tri{};
        std::array<Eigen::Vector3d, 3> pos;
        for (int k = 0; k < 3; ++k) {
          tri[k] = vertex_of_point(corner[k]);
          pos[k] = layout_of_point(corner[k]);
          if (!laid[tri[k]]) {
            laid[tri[k]] = 1;
            out.vertex_layout[tri[k]] = pos[k];
          }
        }
        out.faces.push_back(tri);
        out.corners.push_back(pos);
        out.input_face.push_back(piece.input_face);
        out.final_face.push_back(face);
      }
    }
  }
  out.seconds = detail::seconds_since(begin);
  return out;
}

}  // namespace ricci
