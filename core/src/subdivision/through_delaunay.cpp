#include "subdivision/through_delaunay.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>

#include "flow/delaunay.h"
#include "mesh/plane.h"
#include "ricci/mesh/errors.h"
#include "ricci/mesh/geometry.h"
#include "subdivision/face_pieces.h"
#include "subdivision/input_overlay.h"
#include "subdivision/piece_triangles.h"

namespace ricci::detail {

namespace {

// === Through the input's intrinsic Delaunay triangulation
//
// Yamabe (E2, S2) with isometric flips first: the input Ta is flipped to its intrinsic Delaunay
// triangulation Tb in the metric of its lambda-lengths, then Tb by Ptolemy flips to the final Tc.
// An input edge is straight in Tb's faces drawn in that metric, but bends at Tb's edges in the
// hyperbolic picture where Tc's edges are straight, and the map is projective on each cell of Tb
// and Tc only. So the pieces are the cells of Ta, Tb and Tc together: Tb cut by Tc (an overlay of
// the Ptolemy flips over Tb, exact), each piece then cut, in the Euclidean chart of its face of
// Tb, by the input's edges (an overlay of the isometric flips, exact). A face of Tc is drawn in
// the plane of its chord triangle (in E2 its layout, on S2 the flat triangle of its corners on
// the unit sphere, whose sides are the chords, Euclidean Yamabe lengths); on S2 the points are
// then projected centrally onto the sphere, which is projective too.

// Center and radius of the circle through a, b, c.
std::pair<Eigen::Vector2d, double> circumcircle(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                                const Eigen::Vector2d& c) {
  const Eigen::Vector2d ab = b - a, ac = c - a;
  const double d = 2 * cross(ab, ac);
  const Eigen::Vector2d o =
      a + Eigen::Vector2d(ac.y() * ab.squaredNorm() - ab.y() * ac.squaredNorm(),
                          ab.x() * ac.squaredNorm() - ac.x() * ab.squaredNorm()) /
              d;
  return {o, (o - a).norm()};
}

// A geodesic of the hyperbolic plane drawn as a chord of a circle (a Klein chart): the line through
// p and q. Its points in homogeneous barycentric coordinates of its two ideal ends are straight
// in the chart up to one scale per end, so a parameter s along it (0 and 1 at the ends) is
// projective in the chart's, fixed by one point of known 0 < s < 1 (p's sp or q's sq).
class KleinChord {
 public:
  KleinChord(const std::pair<Eigen::Vector2d, double>& circle, const Eigen::Vector2d& p, double sp,
             const Eigen::Vector2d& q, double sq)
      : p_(p), d_(q - p) {
    const Eigen::Vector2d w = p - circle.first;
    const double qa = d_.squaredNorm(), qb = 2 * w.dot(d_),
                 qc = w.squaredNorm() - circle.second * circle.second;
    const double disc = std::sqrt(std::max(0.0, qb * qb - 4 * qa * qc));
    double lo = (-qb - disc) / (2 * qa), hi = (-qb + disc) / (2 * qa);
    if (sq < sp) std::swap(lo, hi);
    mu0_ = lo, mu1_ = hi;
    const bool use_p = sp > 0 && sp < 1;
    const double s_ref = use_p ? sp : sq, x_ref = x_of(use_p ? 0.0 : 1.0);
    rho_ = odds(s_ref) / odds(x_ref);
  }
  Eigen::Vector2d point(double s) const {
    const double r = odds(s) / rho_, x = r / (1 + r);
    return p_ + (mu0_ + x * (mu1_ - mu0_)) * d_;
  }
  double parameter(const Eigen::Vector2d& z) const {
    const double r = rho_ * odds(x_of((z - p_).dot(d_) / d_.squaredNorm()));
    return r / (1 + r);
  }

 private:
  static double odds(double x) { return x / (1 - x); }
  double x_of(double mu) const { return (mu - mu0_) / (mu1_ - mu0_); }
  Eigen::Vector2d p_, d_;
  double mu0_ = 0, mu1_ = 1, rho_ = 1;
};

// The plane of a final face's chord triangle: E2, the layout itself; S2, the plane through its
// corners on the unit sphere, with 2D coordinates there, and points lifted back by central
// projection onto the sphere.
class ChordPlane {
 public:
  ChordPlane(Geometry g, const std::array<Eigen::Vector3d, 3>& corners)
      : spherical_(g == Geometry::Spherical), origin_(corners[0]) {
    if (!spherical_) return;
    e1_ = (corners[1] - corners[0]).normalized();
    const Eigen::Vector3d d = corners[2] - corners[0];
    e2_ = (d - d.dot(e1_) * e1_).normalized();
  }
  Eigen::Vector3d chart(const Eigen::Vector3d& p) const {
    if (!spherical_) return p;
    const Eigen::Vector3d d = p - origin_;
    return {d.dot(e1_), d.dot(e2_), 0};
  }
  Eigen::Vector3d lift(const Eigen::Vector3d& z) const {
    if (!spherical_) return z;
    return (origin_ + z.x() * e1_ + z.y() * e2_).normalized();
  }

 private:
  bool spherical_;
  Eigen::Vector3d origin_, e1_, e2_;
};

// A vertex of the subdivision beyond the input's: on input edge `input_edge` at parameter s, or
// inside input face `face` (input_edge -1).
struct NewVertex {
  Eigen::Vector3d position;
  int input_edge = -1;
  double s = std::nan("");
  int face = -1;
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();
  double u = 0;
};

// A corner of a piece while it is cut: its vertex (input vertex, or nv + index of a NewVertex),
// its position in the chart of its face F of Tb and in the final layout, and what it lies on.
struct CutPoint {
  int vertex = -1;
  Eigen::Vector2d chart;
  Eigen::Vector3d layout;
  int f_corner = -1;          // a corner of F, or
  int f_side = -1;            // on this side of F (corner f_side to f_side + 1) at
  double f_t = std::nan("");  // this parameter from corner f_side (convention = Euclidean)
  int g_corner = -1;          // a corner of the final face G, or
  int g_side = -1;            // on this side of G at
  double g_t = std::nan("");  // this parameter from corner g_side (convention)
};

// A side of a piece, from its point i to i + 1: on a side of F, a side of G, or an input edge.
struct CutSide {
  int f_side = -1, g_side = -1, chord = -1;
};

struct CutPolygon {
  std::vector<CutPoint> points;
  std::vector<CutSide> sides;
};

struct FourIndexHash {
  size_t operator()(const std::array<int, 4>& k) const {
    std::uint64_t h = 0;
    for (int x : k) h = (h ^ static_cast<std::uint32_t>(x)) * 0x9E3779B97F4A7C15ull;
    return static_cast<size_t>(h ^ (h >> 32));
  }
};

}  // namespace

// Ta cut by Tb cut by Tc; flips[0, split) are the isometric flips.
CommonSubdivision subdivision_through_delaunay(const CompactMesh& mesh,
                                               const ConformalStructure& initial,
                                               const FlowResult& result, const Layout& layout,
                                               size_t split, PieceTriangles how) {
  const std::vector<EdgeFlip>& flips = result.flip_sequence;
  const Geometry geometry = layout.geometry;
  InputOverlay in_delaunay(mesh, true);          // Ta over Tb
  std::vector<double> length(mesh.num_edges());  // lambda-lengths of Tb's edges
  for (int e = 0; e < mesh.num_edges(); ++e) length[e] = std::sqrt(2 * initial.eta[e]);
  for (size_t i = 0; i < split; ++i) {
    const EdgeFlip& f = flips[i];
    // The flow's own length of the new diagonal: unfolded here apex by apex, a needle's diagonal
    // differed from it in its 11th digit, enough to make a face of three vertices on one line
    // flat in the charts and its pieces no surface (a robot forearm's chain of vertices 1e-7
    // apart between faces 0.03 long).
    length[f.edge] = isometric_flip_diagonal(f.lambda);
    in_delaunay.flip(f);
  }
  const Triangulation& Tb = in_delaunay.triangulation();
  InputOverlay over_delaunay(Tb, true);  // Tb over Tc
  for (size_t i = split; i < flips.size(); ++i) over_delaunay.flip(flips[i]);
  const Triangulation& Tc = over_delaunay.triangulation();
  if (Tc.faces() != result_triangulation(mesh, result).faces() ||
      static_cast<int>(layout.corners.size()) != Tc.num_faces()) {
    throw LayoutError(
        "common subdivision: the replayed flips do not give the flow's triangulation");
  }
  const int nv = mesh.num_vertices();
  const std::vector<Crossing>& ab_crossings = in_delaunay.crossings();
  const std::vector<Crossing>& bc_crossings = over_delaunay.crossings();
  std::vector<std::vector<int>> vertex_faces(nv);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) vertex_faces[mesh.face_vertex(f, k)].push_back(f);
  }

  // === New vertices
  std::vector<NewVertex> added;
  auto add = [&](const NewVertex& v) {
    added.push_back(v);
    return nv + static_cast<int>(added.size()) - 1;
  };
  auto on_input_edge = [&](int E, double s) {
    const auto [a, b] = mesh.edge_vertices(E);
    NewVertex v;
    v.position = (1 - s) * mesh.positions()[a] + s * mesh.positions()[b];
    v.input_edge = E;
    v.s = s;
    v.face = mesh.edge_faces(E)[0];
    for (int k = 0; k < 3; ++k) {
      if (mesh.face_vertex(v.face, k) == a) v.barycentric[k] = 1 - s;
      if (mesh.face_vertex(v.face, k) == b) v.barycentric[k] = s;
    }
    v.u = (1 - s) * result.u[a] + s * result.u[b];
    return add(v);
  };
  std::vector<int> ab_vertex(ab_crossings.size(), -1), bc_vertex(bc_crossings.size(), -1);
  auto ab_point = [&](int c) {
    if (ab_vertex[c] < 0)
      ab_vertex[c] = on_input_edge(ab_crossings[c].input_edge, ab_crossings[c].s);
    return ab_vertex[c];
  };
  double layout_size = 0;  // the diagonal of the layout's bounding box
  {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()),
                    hi = -lo;
    for (const auto& corners : layout.corners) {
      for (const Eigen::Vector3d& p : corners) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    }
    layout_size = (hi - lo).norm();
  }
  // A point of Tb's edge eb at parameter s: straight in the input faces between the crossings of
  // the input's edges along it.
  auto on_delaunay_edge = [&](int eb, double s) {
    const int E = in_delaunay.coincident_input_edge(eb);
    const int a = Tb.edge_vertices(eb)[0], b = Tb.edge_vertices(eb)[1];
    if (E >= 0) return on_input_edge(E, mesh.edge_vertices(E)[0] == a ? s : 1 - s);
    const std::vector<int> list = in_delaunay.crossings_on(eb);
    // Where an edge of Tc crosses eb at an input edge's crossing, or nearer to it than float
    // texture coordinates resolve (1e-6 of the layout's size, the gap measured in eb's length
    // l e^((ua + ub) / 2) of the final metric), the two are one vertex, on the input edge: else
    // the sliver between them turns over in the texture (elk: Tc edges that are input edges
    // flipped back cross eb 1e-8 of the layout's size from them). Never farther apart than 1e-4
    // of eb, though: where the metric squeezes eb far below the layout's size, distinct crossings
    // merged would make edges shared by three faces (a cow's atlas at 6 cones, D 1.6).
    // In S2 the lambda-lengths are half the chords.
    const double final_length = (geometry == Geometry::Spherical ? 2 : 1) * length[eb] *
                                std::exp((result.u[a] + result.u[b]) / 2);
    // Only the input edges' crossings next to s along eb, the nearer first: merged with one
    // beyond another, the vertex would lie on the far side of that input edge (cura-zav-maxpro's
    // atlas: a Tc crossing at 3.91e-5 of a sliver's side made one with an input edge's crossing
    // at 4.29e-5, across another's at 4.01e-5, and the two input edges crossed in the chart).
    size_t k = 0;
    while (k < list.size() && ab_crossings[list[k]].t <= s) ++k;
    std::array<int, 2> next_to = {k > 0 ? list[k - 1] : -1, k < list.size() ? list[k] : -1};
    if (next_to[0] < 0 || (next_to[1] >= 0 && std::abs(ab_crossings[next_to[1]].t - s) <
                                                  std::abs(ab_crossings[next_to[0]].t - s))) {
      std::swap(next_to[0], next_to[1]);
    }
    // And only where no other edge of Tc crosses eb as near to that crossing or nearer (this one
    // among them): two merged with one would close the face of Tc between them to a point (edges
    // shared by three faces).
    const auto alone_within = [&](double t, double gap) {
      int near = 0;
      for (int x = over_delaunay.first_crossing(eb); x >= 0; x = bc_crossings[x].next)
        near += std::abs(bc_crossings[x].s - t) <= gap;
      return near == 1;
    };
    for (int c : next_to) {
      if (c < 0) continue;
      const double gap = std::abs(ab_crossings[c].t - s);
      if (gap * final_length <= 1e-6 * layout_size && gap <= 1e-4 &&
          alone_within(ab_crossings[c].t, gap)) {
        return ab_point(c);
      }
    }
    struct Station {
      double t;
      int vertex, crossing;
    };
    const Station s0 =
        k == 0 ? Station{0.0, a, -1} : Station{ab_crossings[list[k - 1]].t, -1, list[k - 1]};
    const Station s1 =
        k == list.size() ? Station{1.0, b, -1} : Station{ab_crossings[list[k]].t, -1, list[k]};
    auto faces_of = [&](const Station& st) {
      if (st.vertex >= 0) return vertex_faces[st.vertex];
      const auto& f = mesh.edge_faces(ab_crossings[st.crossing].input_edge);
      std::vector<int> out = {f[0]};
      if (f[1] >= 0) out.push_back(f[1]);
      return out;
    };
    const std::vector<int> f0 = faces_of(s0), f1 = faces_of(s1);
    int face = -1;
    for (int f : f0) {
      if (face < 0 && std::find(f1.begin(), f1.end(), f) != f1.end()) face = f;
    }
    if (face < 0)
      throw LayoutError(
          "common subdivision: an edge of the input's Delaunay triangulation leaves the input "
          "faces");
    auto barycentric = [&](const Station& st) {
      Eigen::Vector3d bary = Eigen::Vector3d::Zero();
      for (int k2 = 0; k2 < 3; ++k2) {
        const int v = mesh.face_vertex(face, k2);
        if (st.vertex >= 0) {
          if (v == st.vertex) bary[k2] = 1;
          continue;
        }
        const Crossing& x = ab_crossings[st.crossing];
        const auto& ends = mesh.edge_vertices(x.input_edge);
        if (v == ends[0]) bary[k2] = 1 - x.s;
        if (v == ends[1]) bary[k2] = x.s;
      }
      return bary;
    };
    const double mu = s1.t > s0.t ? (s - s0.t) / (s1.t - s0.t) : 0.5;
    NewVertex v;
    v.face = face;
    v.barycentric = (1 - mu) * barycentric(s0) + mu * barycentric(s1);
    v.position = Eigen::Vector3d::Zero();
    for (int k2 = 0; k2 < 3; ++k2) {
      const int w = mesh.face_vertex(face, k2);
      v.position += v.barycentric[k2] * mesh.positions()[w];
      v.u += v.barycentric[k2] * result.u[w];
    }
    return add(v);
  };
  auto bc_point = [&](int c) {
    if (bc_vertex[c] < 0)
      bc_vertex[c] = on_delaunay_edge(bc_crossings[c].input_edge, bc_crossings[c].s);
    return bc_vertex[c];
  };
  std::unordered_map<std::array<int, 4>, int, FourIndexHash>
      ac_vertex;  // (F, chord, ends of the side of G)
  // Per new vertex on an input edge, its layout in the final face G at hand (pieces of G that
  // share it draw it at one point); a few per face, cleared at the next.
  std::vector<std::pair<int, Eigen::Vector3d>> layout_in;
  const auto layout_in_g = [&](int v) -> const Eigen::Vector3d* {
    for (const auto& [w, at] : layout_in) {
      if (w == v) return &at;
    }
    return nullptr;
  };
  const auto keep_layout_in_g = [&](int v, const Eigen::Vector3d& at) {
    if (!layout_in_g(v)) layout_in.emplace_back(v, at);
  };

  // === The input's edges in the Euclidean chart of each face of Tb
  struct ChordEnd {
    CutPoint point;
    double s = 0;  // along the input edge
  };
  struct Chord {
    int input_edge = -1;
    std::array<ChordEnd, 2> end;  // s increasing
  };
  auto chart_of = [&](int F) {
    const double c = length[Tb.face_edge(F, 2)], a = length[Tb.face_edge(F, 0)],
                 b = length[Tb.face_edge(F, 1)];
    const auto [x, y] = triangle_apex(c, b, a);
    return std::array<Eigen::Vector2d, 3>{Eigen::Vector2d(0, 0), Eigen::Vector2d(c, 0),
                                          Eigen::Vector2d(x, y)};
  };
  auto side_of_edge = [&](int F, int eb) {
    for (int k = 0; k < 3; ++k) {
      if (Tb.face_edge(F, (k + 2) % 3) == eb) return k;
    }
    return -1;
  };
  auto corner_of_vertex = [&](int F, int v) {
    for (int k = 0; k < 3; ++k) {
      if (Tb.face_vertex(F, k) == v) return k;
    }
    return -1;
  };
  // The chords of every face F of Tb one after another, F's from chords_of[F][0] to [1], made
  // when a piece of F is first cut (a vector per face: man's subdivision at 8 cones 0.121 s
  // against 0.118).
  std::vector<Chord> chords;
  std::vector<std::array<size_t, 2>> chords_of(Tb.num_faces());
  auto chords_in = [&](int F, const std::array<Eigen::Vector2d, 3>& z) {
    chords_of[F][0] = chords.size();
    auto crossing_end = [&](int c) {
      const Crossing& x = ab_crossings[c];
      ChordEnd end;
      end.s = x.s;
      end.point.vertex = ab_point(c);
      end.point.f_side = side_of_edge(F, x.edge);
      const int k = end.point.f_side;
      end.point.f_t = Tb.edge_vertices(x.edge)[0] == Tb.face_vertex(F, k) ? x.t : 1 - x.t;
      end.point.chart = (1 - end.point.f_t) * z[k] + end.point.f_t * z[(k + 1) % 3];
      return end;
    };
    auto vertex_end = [&](int v, double s) {
      ChordEnd end;
      end.s = s;
      end.point.vertex = v;
      end.point.f_corner = corner_of_vertex(F, v);
      end.point.chart = z[end.point.f_corner];
      return end;
    };
    for (int k = 0; k < 3; ++k) {
      const int eb = Tb.face_edge(F, (k + 2) % 3);
      for (int c : in_delaunay.crossings_on(eb)) {
        const Crossing& x = ab_crossings[c];
        const auto& faces = Tb.edge_faces(eb);
        const int from = x.forward ? faces[0] : faces[1], to = x.forward ? faces[1] : faces[0];
        const auto& ends = mesh.edge_vertices(x.input_edge);
        if (from == F) {
          chords.push_back(
              {x.input_edge,
               {x.prev >= 0 ? crossing_end(x.prev) : vertex_end(ends[0], 0), crossing_end(c)}});
        }
        if (to == F && x.next < 0) {
          chords.push_back({x.input_edge, {crossing_end(c), vertex_end(ends[1], 1)}});
        }
      }
    }
    chords_of[F][1] = chords.size();
  };

  // The pieces of face F of Tb between the input's edges (the first overlay's), convex in F's
  // chart: their corners there, counter-clockwise, and their input faces. All faces' pieces one
  // after another, their corners too (a vector per face cost man's subdivision a tenth of it).
  struct InputPiece {
    size_t begin = 0, end = 0;  // its corners in piece_corners
    int input_face = -1;
  };
  std::vector<Eigen::Vector2d> piece_corners;
  std::vector<InputPiece> pieces_made;
  std::vector<std::array<size_t, 2>> pieces_in(Tb.num_faces());  // per F: its pieces in pieces_made
  auto make_input_pieces = [&](int F, const std::array<Eigen::Vector2d, 3>& z) {
    const FaceCut cut = cut_face(in_delaunay, F);
    pieces_in[F][0] = pieces_made.size();
    for (const FacePiece& piece : cut.pieces) {
      InputPiece out;
      out.input_face = piece.input_face;
      out.begin = piece_corners.size();
      for (int p : piece.points) {
        const BoundaryPoint& b = cut.points[p];
        if (b.corner >= 0) {
          piece_corners.push_back(z[b.corner]);
        } else {
          const double t = in_delaunay.t_on_side(b.crossing, F, b.side);
          piece_corners.push_back((1 - t) * z[b.side] + t * z[(b.side + 1) % 3]);
        }
      }
      out.end = piece_corners.size();
      pieces_made.push_back(out);
    }
    pieces_in[F][1] = pieces_made.size();
  };
  // The input face holding a cell in face F of Tb: that of the piece of F deepest around the
  // cell's centroid, not of the corners the cell touches (one may lie within rounding of an
  // input edge).
  auto input_face_of = [&](int F, const CutPolygon& cell) {
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (const CutPoint& p : cell.points) centroid += p.chart;
    centroid /= static_cast<double>(cell.points.size());
    int input_face = -1;
    double deepest = -std::numeric_limits<double>::infinity();
    for (size_t k = pieces_in[F][0]; k < pieces_in[F][1]; ++k) {
      const InputPiece& piece = pieces_made[k];
      const Eigen::Vector2d* corners = piece_corners.data() + piece.begin;
      double depth = std::numeric_limits<double>::infinity();
      const size_t n = piece.end - piece.begin;
      for (size_t i = 0; i < n; ++i) {
        const Eigen::Vector2d &a = corners[i], d = corners[(i + 1) % n] - a;
        if (d.squaredNorm() > 0) depth = std::min(depth, cross(d, centroid - a) / d.norm());
      }
      if (depth > deepest) input_face = piece.input_face, deepest = depth;
    }
    return input_face;
  };

  // === Cutting the pieces of Tb and Tc
  CommonSubdivision out;
  // The cells' points one after another (cell c's from cell_begin[c] to cell_begin[c + 1]): one
  // array, not a vector per cell, whose frees cost man's subdivision (35k cells) a sixth of it.
  std::vector<CutPoint> cell_points;
  std::vector<size_t> cell_begin = {0};
  std::vector<int> cell_face, cell_input_face;
  cell_points.reserve(3 * static_cast<size_t>(Tc.num_faces()));
  cell_begin.reserve(Tc.num_faces() + 1), cell_face.reserve(Tc.num_faces());
  cell_input_face.reserve(Tc.num_faces());
  auto fail = [&](int G, const std::string& what) {
    throw LayoutError("common subdivision: face " + std::to_string(G) +
                      " of the final triangulation: " + what);
  };
  std::vector<ChordPlane> planes;
  planes.reserve(Tc.num_faces());
  std::vector<char> made_for(Tb.num_faces(), 0);
  for (int G = 0; G < Tc.num_faces(); ++G) {
    planes.emplace_back(geometry, layout.corners[G]);
    std::array<Eigen::Vector3d, 3> gc;  // G's corners in the plane of its chords
    for (int k = 0; k < 3; ++k) gc[k] = planes.back().chart(layout.corners[G][k]);
    const auto circle_g = circumcircle(gc[0].head<2>(), gc[1].head<2>(), gc[2].head<2>());
    auto g_layout = [&](int side, double t) {
      const int v = Tc.face_vertex(G, side), w = Tc.face_vertex(G, (side + 1) % 3);
      return between(Geometry::Euclidean, gc[side], gc[(side + 1) % 3],
                     realize(over_delaunay, t, v, w, result.u), DiskSidePoints::OnGeodesic);
    };
    const FaceCut cut = cut_face(over_delaunay, G);
    layout_in.clear();
    // A crossing of Tb's and Tc's edges that on_delaunay_edge made an input edge's crossing is
    // drawn on G's side, in each piece of G that holds it.
    for (const BoundaryPoint& b : cut.points) {
      if (b.crossing < 0) continue;
      const int v = bc_point(b.crossing);
      if (v >= nv && added[v - nv].input_edge >= 0) {
        keep_layout_in_g(v, g_layout(b.side, over_delaunay.t_on_side(b.crossing, G, b.side)));
      }
    }
    for (const FacePiece& piece : cut.pieces) {
      const int F = piece.input_face;
      const std::array<Eigen::Vector2d, 3> z = chart_of(F);
      const auto circle_f = circumcircle(z[0], z[1], z[2]);
      CutPolygon poly;
      poly.points.reserve(piece.points.size());
      poly.sides.reserve(piece.points.size());
      for (int p : piece.points) {
        const BoundaryPoint& b = cut.points[p];
        CutPoint q;
        if (b.corner >= 0) {
          q.vertex = Tc.face_vertex(G, b.corner);
          q.g_corner = b.corner;
          q.layout = gc[b.corner];
          q.f_corner = corner_of_vertex(F, q.vertex);
          if (q.f_corner < 0) fail(G, "a corner outside its face of the Delaunay triangulation");
          q.chart = z[q.f_corner];
        } else {
          const Crossing& x = bc_crossings[b.crossing];
          q.vertex = bc_point(b.crossing);
          q.g_side = b.side;
          q.g_t = over_delaunay.t_on_side(b.crossing, G, b.side);
          q.layout = g_layout(b.side, q.g_t);
          q.f_side = side_of_edge(F, x.input_edge);
          if (q.f_side < 0) fail(G, "a crossing outside its face of the Delaunay triangulation");
          const int k = q.f_side;
          q.f_t = Tb.edge_vertices(x.input_edge)[0] == Tb.face_vertex(F, k) ? x.s : 1 - x.s;
          q.chart = (1 - q.f_t) * z[k] + q.f_t * z[(k + 1) % 3];
        }
        poly.points.push_back(q);
      }
      const size_t n = poly.points.size();
      for (size_t i = 0; i < n; ++i) {
        CutSide side;
        if (piece.arc[i]) side.g_side = cut.points[piece.points[i]].side;
        if (piece.along[i] >= 0) {
          const CutPoint &p = poly.points[i], &q = poly.points[(i + 1) % n];
          for (int k = 0; k < 3; ++k) {
            auto on = [&](const CutPoint& r) {
              return r.f_side == k || r.f_corner == k || r.f_corner == (k + 1) % 3;
            };
            if (Tb.face_edge(F, (k + 2) % 3) == piece.along[i] && on(p) && on(q)) side.f_side = k;
          }
          if (side.f_side < 0) fail(G, "a side of a piece on no side of the Delaunay face");
        }
        poly.sides.push_back(side);
      }
      // Parameters of a point along side k of F (from corner k) and side k of G.
      auto f_param = [](const CutPoint& r, int k) {
        return r.f_side == k ? r.f_t : (r.f_corner == k ? 0.0 : 1.0);
      };
      auto g_param = [](const CutPoint& r, int k) {
        return r.g_side == k ? r.g_t : (r.g_corner == k ? 0.0 : 1.0);
      };
      // The point where chord `ch` (number ci) crosses side i of `poly`.
      auto crossing_point = [&](const CutPolygon& pl, size_t i, const Chord& ch, int ci,
                                double sigma) {
        const CutPoint &P = pl.points[i], &Q = pl.points[(i + 1) % pl.points.size()];
        const CutSide& S = pl.sides[i];
        if (S.f_side >= 0) {
          const ChordEnd* e = nullptr;
          for (const ChordEnd& end : ch.end) {
            if (end.point.f_side == S.f_side) e = &end;
          }
          if (!e) fail(G, "an input edge crosses a side of its Delaunay face twice");
          CutPoint q = e->point;
          if (S.g_side >= 0) {
            q.g_side = S.g_side;
            q.g_t = Tc.face_vertex(G, S.g_side) == Tb.face_vertex(F, S.f_side) ? q.f_t : 1 - q.f_t;
            q.layout = g_layout(q.g_side, q.g_t);
            keep_layout_in_g(q.vertex, q.layout);
          } else if (const Eigen::Vector3d* kept = layout_in_g(q.vertex)) {
            q.layout = *kept;
          } else {
            const KleinChord line(circle_g, P.layout.head<2>(), f_param(P, S.f_side),
                                  Q.layout.head<2>(), f_param(Q, S.f_side));
            const Eigen::Vector2d at = line.point(q.f_t);
            q.layout = Eigen::Vector3d(at.x(), at.y(), P.layout.z());
            layout_in.emplace_back(q.vertex, q.layout);
          }
          return q;
        }
        if (S.g_side < 0) {
          fail(G, "two input edges cross in a face of the Delaunay triangulation");
        }
        CutPoint q;
        q.chart = P.chart + sigma * (Q.chart - P.chart);
        q.g_side = S.g_side;
        const KleinChord line(circle_f, P.chart, g_param(P, S.g_side), Q.chart,
                              g_param(Q, S.g_side));
        q.g_t = std::clamp(line.parameter(q.chart), 0.0, 1.0);
        q.layout = g_layout(q.g_side, q.g_t);
        const std::array<int, 4> key = {F, ci, std::min(P.vertex, Q.vertex),
                                        std::max(P.vertex, Q.vertex)};
        if (const auto it = ac_vertex.find(key); it != ac_vertex.end()) {
          q.vertex = it->second;
        } else {
          const Eigen::Vector2d a0 = ch.end[0].point.chart, d = ch.end[1].point.chart - a0;
          const double mu = std::clamp((q.chart - a0).dot(d) / d.squaredNorm(), 0.0, 1.0);
          q.vertex = on_input_edge(ch.input_edge, ch.end[0].s + mu * (ch.end[1].s - ch.end[0].s));
          ac_vertex.emplace(key, q.vertex);
        }
        return q;
      };
      std::vector<CutPolygon> parts;
      parts.push_back(std::move(poly));
      // F's chords and input pieces, made once for all the pieces of the faces G that F meets (made
      // for each, they cost CGAL's cheese at 8 cones most of its subdivision: a face F of Tb can
      // meet hundreds of G, and hold hundreds of crossings).
      if (!made_for[F]) {
        chords_in(F, z);
        make_input_pieces(F, z);
        made_for[F] = 1;
      }
      const size_t first_chord = chords_of[F][0];
      for (size_t ci = 0; ci < chords_of[F][1] - first_chord; ++ci) {
        const Chord& ch = chords[first_chord + ci];
        const Eigen::Vector2d a0 = ch.end[0].point.chart, dir = ch.end[1].point.chart - a0;
        std::vector<CutPolygon> next;
        for (const CutPolygon& pl : parts) {
          const size_t m = pl.points.size();
          std::vector<double> d(m);
          bool above = false, below = false;
          for (size_t i = 0; i < m; ++i) {
            const CutPoint& r = pl.points[i];
            const bool end =
                r.vertex == ch.end[0].point.vertex || r.vertex == ch.end[1].point.vertex;
            // A point within rounding of the line is on it (an input edge through a crossing of
            // the two triangulations' edges), so that no piece is cut to nothing.
            d[i] = end ? 0.0 : cross(dir, r.chart - a0);
            if (std::abs(d[i]) <= 1e-10 * dir.squaredNorm()) d[i] = 0;
            above = above || d[i] > 0;
            below = below || d[i] < 0;
          }
          if (!above || !below) {
            next.push_back(pl);
            continue;
          }
          struct Item {
            CutPoint point;
            CutSide side;
            double d;
          };
          std::vector<Item> seq;
          for (size_t i = 0; i < m; ++i) {
            const size_t j = (i + 1) % m;
            seq.push_back({pl.points[i], pl.sides[i], d[i]});
            if ((d[i] > 0 && d[j] < 0) || (d[i] < 0 && d[j] > 0)) {
              seq.push_back({crossing_point(pl, i, ch, static_cast<int>(ci), d[i] / (d[i] - d[j])),
                             pl.sides[i], 0.0});
            }
          }
          for (const double sign : {1.0, -1.0}) {
            std::vector<size_t> keep;
            for (size_t i = 0; i < seq.size(); ++i) {
              if (sign * seq[i].d >= 0) keep.push_back(i);
            }
            CutPolygon half;
            for (size_t i = 0; i < keep.size(); ++i) {
              const size_t a = keep[i], b = keep[(i + 1) % keep.size()];
              half.points.push_back(seq[a].point);
              CutSide chord_side;
              chord_side.chord = static_cast<int>(ci);
              half.sides.push_back(b == (a + 1) % seq.size() ? seq[a].side : chord_side);
            }
            if (half.points.size() >= 3) next.push_back(std::move(half));
          }
        }
        parts = std::move(next);
      }
      for (CutPolygon& pl : parts) {
        cell_input_face.push_back(input_face_of(F, pl));
        cell_points.insert(cell_points.end(), pl.points.begin(), pl.points.end());
        cell_begin.push_back(cell_points.size());
        cell_face.push_back(G);
      }
    }
  }

  // === Numbering: new vertices on input edges, edge after edge along each, then the others.
  std::vector<int> order(added.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const NewVertex &x = added[a], &y = added[b];
    const int ex = x.input_edge < 0 ? mesh.num_edges() : x.input_edge,
              ey = y.input_edge < 0 ? mesh.num_edges() : y.input_edge;
    return ex != ey ? ex < ey : (x.input_edge >= 0 && x.s < y.s);
  });
  std::vector<int> number(nv + added.size());
  for (int v = 0; v < nv; ++v) number[v] = v;
  out.num_input_vertices = nv;
  out.num_flips = in_delaunay.num_flips() + over_delaunay.num_flips();
  place_input_vertices(mesh, result, static_cast<int>(added.size()), out);
  for (size_t i = 0; i < order.size(); ++i) {
    const NewVertex& x = added[order[i]];
    number[nv + order[i]] = nv + static_cast<int>(i);
    out.positions.push_back(x.position);
    out.vertex_input_edge.push_back(x.input_edge);
    out.vertex_edge_parameter.push_back(x.s);
    out.vertex_input_face.push_back(x.face);
    out.vertex_barycentric.push_back(x.barycentric);
    out.u[nv + static_cast<long>(i)] = x.u;
  }
  out.vertex_layout.assign(out.positions.size(), Eigen::Vector3d::Constant(std::nan("")));
  std::vector<char> laid(out.positions.size(), 0);

  // === The faces: each cell cut into triangles as `how` asks, in its face of Tb's chart and its
  // layout.
  std::vector<Eigen::Vector2d> domain, image;
  for (size_t c = 0; c < cell_face.size(); ++c) {
    const CutPoint* cell = cell_points.data() + cell_begin[c];
    const int input_face = cell_input_face[c];
    if (input_face < 0) fail(cell_face[c], "a piece lies in no input face");
    domain.clear(), image.clear();
    for (size_t i = cell_begin[c]; i < cell_begin[c + 1]; ++i) {
      domain.push_back(cell_points[i].chart);
      image.push_back(cell_points[i].layout.head<2>());
    }
    const std::vector<std::array<size_t, 3>> triangles = piece_triangles(domain, image, how);
    for (const std::array<size_t, 3>& corner : triangles) {
      std::array<int, 3> tri{};
      std::array<Eigen::Vector3d, 3> pos;
      for (int k = 0; k < 3; ++k) {
        const CutPoint& p = cell[corner[k]];
        tri[k] = number[p.vertex];
        pos[k] = planes[cell_face[c]].lift(p.layout);
        if (!laid[tri[k]]) {
          laid[tri[k]] = 1;
          out.vertex_layout[tri[k]] = pos[k];
        }
      }
      out.faces.push_back(tri);
      out.corners.push_back(pos);
      out.input_face.push_back(input_face);
      out.final_face.push_back(cell_face[c]);
    }
  }
  return out;
}

}  // namespace ricci::detail
