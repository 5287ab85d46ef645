#include "subdivision/input_overlay.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <Eigen/Core>

#include "mesh/plane.h"
#include "ricci/mesh/errors.h"
#include "ricci/mesh/geometry.h"

namespace ricci::detail {

namespace {

// Apex of the triangle on `base` = (p, q) with sides x = |apex - p| and y = |apex - q|, on the
// left of p -> q when `left`.
Eigen::Vector2d apex(const Eigen::Vector2d& p, const Eigen::Vector2d& q, double x, double y,
                     bool left) {
  const Eigen::Vector2d d = q - p;
  const double c = d.norm();
  const auto [along, h] = triangle_apex(c, x, y);
  const Eigen::Vector2d n(-d.y() / c, d.x() / c);
  return p + d * (along / c) + (left ? h : -h) * n;
}

}  // namespace

// A point of an input edge inside a quadrilateral: a crossing, or one of the edge's two vertices
// at a corner of the quadrilateral (local index 0..3: a vertex can be two of its corners).
struct InputOverlay::Point {
  int crossing = -1;
  int vertex = -1;
  int corner = -1;
};

// The piece of an input edge inside the quadrilateral of a flip, in the input edge's direction:
// from p0 over (optionally) a crossing m of the flipped diagonal to p1.
struct InputOverlay::Strand {
  int input_edge = -1;
  Point p0, p1;
  int m = -1;
};

// The quadrilateral k, a, l, b of a flip (local indices 0..3) in a planar picture in which every
// input strand and the new diagonal are straight: positions z and, per corner, the weight w that
// turns the convention's barycentric coordinates into those of the picture (b_v w_v, normalized).
// Its corners are told apart by their place, not their vertices: k and l are one vertex where
// the flip makes an edge from a vertex to itself (a loop, as intrinsic Delaunay triangulations
// may need).
struct InputOverlay::Quad {
  int e = -1, f = -1, g = -1;
  std::array<int, 4> vertex{};  // k, a, l, b
  int e_ka = -1, e_al = -1, e_lb = -1, e_bk = -1;
  // The halfedges a -> b (of e, in f), k -> a, b -> k (in f), a -> l, l -> b (in g).
  int h_ab = -1, h_ka = -1, h_bk = -1, h_al = -1, h_lb = -1;
  std::array<Eigen::Vector2d, 4> z;
  std::array<double, 4> w{1, 1, 1, 1};
  bool circle = false;  // the picture is the circle through the four vertices (unit circle)
};

InputOverlay::InputOverlay(const Triangulation& input, bool projective)
    : input_(input),
      current_(input),
      projective_(projective),
      on_edge_(input.num_edges()),
      coincident_(input.num_edges()),
      first_(input.num_edges(), -1) {
  for (int e = 0; e < input.num_edges(); ++e) coincident_[e] = e;
}

bool InputOverlay::runs_from_tail(int h) const {
  const int e = current_.face_edge(h / 3, h % 3);
  const auto& ends = current_.edge_vertices(e);
  if (ends[0] != ends[1]) return current_.halfedge_tail(h) == ends[0];
  return h == current_.edge_halfedge(e);
}

double InputOverlay::t_along(int c, int h) const {
  const double t = crossings_[c].t;
  return runs_from_tail(h) ? t : 1 - t;
}

std::vector<int> InputOverlay::crossings_on(int edge) const {
  std::vector<int> list = on_edge_[edge];
  std::sort(list.begin(), list.end(),
            [&](int a, int b) { return crossings_[a].t < crossings_[b].t; });
  return list;
}

int InputOverlay::add_crossing(const Crossing& c) {
  if (!free_.empty()) {
    const int id = free_.back();
    free_.pop_back();
    crossings_[id] = c;
    return id;
  }
  crossings_.push_back(c);
  return static_cast<int>(crossings_.size()) - 1;
}

std::vector<InputOverlay::Strand> InputOverlay::strands_through(const Quad& q) const {
  enum { K = 0, A = 1, L = 2, B = 3 };
  std::vector<Strand> strands;
  // The point before (after) crossing c along its input edge: a crossing, or the edge's end at
  // `corner` of the quadrilateral.
  auto neighbour = [&](int c, bool after, int corner) {
    const Crossing& x = crossings_[c];
    const int next = after ? x.next : x.prev;
    Point p;
    if (next >= 0) {
      p.crossing = next;
    } else {
      p.vertex = input_.edge_vertices(x.input_edge)[after ? 1 : 0];
      p.corner = corner;
    }
    return p;
  };
  // A strand from a vertex to a crossing of e starts at the corner of its face off e: k in f,
  // l in g.
  for (int c : on_edge_[q.e]) {
    const Crossing& x = crossings_[c];
    const auto& faces = current_.edge_faces(q.e);
    const int from = x.forward ? faces[0] : faces[1], to = x.forward ? faces[1] : faces[0];
    strands.push_back({x.input_edge, neighbour(c, false, from == q.f ? K : L),
                       neighbour(c, true, to == q.f ? K : L), c});
  }
  // A strand from a vertex to a crossing of a side, within the side's face, starts at the corner
  // opposite the side: b for k-a and a-l, a for b-k and l-b.
  const std::array<std::pair<int, int>, 4> sides = {
      {{q.e_ka, B}, {q.e_al, B}, {q.e_lb, A}, {q.e_bk, A}}};
  for (const auto& [side, opposite] : sides) {
    for (int c : on_edge_[side]) {
      const Crossing& x = crossings_[c];
      const auto& faces = current_.edge_faces(side);
      const int from = x.forward ? faces[0] : faces[1], to = x.forward ? faces[1] : faces[0];
      const bool from_quad = from == q.f || from == q.g, to_quad = to == q.f || to == q.g;
      if (from_quad && !(x.prev >= 0 && crossings_[x.prev].edge == q.e)) {
        strands.push_back({x.input_edge, neighbour(c, false, opposite), {c, -1, -1}, -1});
      }
      if (to_quad && x.next < 0) {
        strands.push_back({x.input_edge, {c, -1, -1}, neighbour(c, true, opposite), -1});
      }
    }
  }
  // An input edge along e runs from a to b or from b to a (never a loop: input edges join two
  // vertices).
  if (coincident_[q.e] >= 0) {
    const int E = coincident_[q.e];
    const auto& ends = input_.edge_vertices(E);
    const bool from_a = ends[0] == q.vertex[A];
    strands.push_back({E, {-1, ends[0], from_a ? A : B}, {-1, ends[1], from_a ? B : A}, -1});
  }
  return strands;
}

void InputOverlay::flip(const EdgeFlip& record) {
  const int e = record.edge;
  const Triangulation& T = current_;
  auto fail = [&](const std::string& what) {
    throw LayoutError("common subdivision: flip " + std::to_string(num_flips_ + 1) + " (edge " +
                      std::to_string(e) + "): " + what);
  };
  if (T.is_boundary_edge(e)) fail("a boundary edge");
  Quad q;
  q.e = e;
  const int h = T.edge_halfedge(e), tw = T.twin(h);
  q.f = h / 3;
  q.g = tw / 3;
  const int c = h % 3, d = tw % 3;
  q.vertex = {T.face_vertex(q.f, c), T.face_vertex(q.f, (c + 1) % 3), T.face_vertex(q.g, d),
              T.face_vertex(q.f, (c + 2) % 3)};
  q.e_bk = T.face_edge(q.f, (c + 1) % 3);
  q.e_ka = T.face_edge(q.f, (c + 2) % 3);
  q.e_al = T.face_edge(q.g, (d + 1) % 3);
  q.e_lb = T.face_edge(q.g, (d + 2) % 3);
  q.h_ab = h;
  q.h_bk = 3 * q.f + (c + 1) % 3;
  q.h_ka = 3 * q.f + (c + 2) % 3;
  q.h_al = 3 * q.g + (d + 1) % 3;
  q.h_lb = 3 * q.g + (d + 2) % 3;
  enum { K = 0, A = 1, L = 2, B = 3 };
  // Four sides that are four edges, each in one face of the quadrilateral (as the strands below
  // are followed).
  if (!T.flips_to_triangles(e)) fail("two sides of the quadrilateral are one edge");
  // The corners at the ends of crossing x's edge, the first where its t starts.
  const auto ends_of = [&](const Crossing& x) -> std::array<int, 2> {
    const auto oriented = [&](int side, int tail, int head) -> std::array<int, 2> {
      return runs_from_tail(side) ? std::array<int, 2>{tail, head} : std::array<int, 2>{head, tail};
    };
    if (x.edge == e) return oriented(q.h_ab, A, B);
    if (x.edge == q.e_ka) return oriented(q.h_ka, K, A);
    if (x.edge == q.e_bk) return oriented(q.h_bk, B, K);
    if (x.edge == q.e_al) return oriented(q.h_al, A, L);
    if (x.edge == q.e_lb) return oriented(q.h_lb, L, B);
    fail("a strand's crossing lies on no side of the quadrilateral");
    return {-1, -1};
  };

  // The planar picture.
  // An isometric flip of the input's metric (before the flow, EdgeFlip::isometric): the unfolded
  // quadrilateral of its Euclidean lengths, where straight is straight; its parameters are then
  // the Euclidean ones, which the lambda-lengths of the flips after it share.
  const bool circle = !record.isometric && (projective_ || record.ptolemy);
  const std::array<double, 5>& len =
      projective_ && !record.isometric ? record.lambda : record.chord;
  const double ka = len[0], al = len[1], lb = len[2], bk = len[3], ab = len[4];
  if (circle) {
    // k, a, b at fixed points of the unit circle; the scales s_v with chord = s_u s_v lambda fit
    // the triangle (k, a, b); l on the lower arc where its chords to a and b have the ratio of
    // the scaled lambdas (Ptolemy's relation then holds for the fourth chord).
    q.circle = true;
    q.z[A] = {-1, 0};
    q.z[B] = {1, 0};
    q.z[K] = {0, 1};
    const double sa2 = 2 * bk / (ab * ka), sb2 = 2 * ka / (ab * bk);
    const double sa = std::sqrt(sa2), sb = std::sqrt(sb2);
    const double sk = std::sqrt(2.0) / (sa * ka);
    const double r = (sa * al) / (sb * lb);
    const double theta = kPi + 2 * std::atan(r);
    q.z[L] = {std::cos(theta), std::sin(theta)};
    const double sl = (q.z[L] - q.z[A]).norm() / (sa * al);
    q.w = {1 / (sk * sk), 1 / sa2, 1 / (sl * sl), 1 / sb2};
  } else {
    q.z[A] = {0, 0};
    q.z[B] = {ab, 0};
    q.z[K] = apex(q.z[A], q.z[B], ka, bk, true);
    q.z[L] = apex(q.z[A], q.z[B], al, lb, false);
  }
  for (const auto& p : q.z) {
    if (!p.allFinite()) fail("the quadrilateral has no planar picture");
  }

  // Position of a point in the picture, and its parameter along its input edge.
  auto place = [&](const Point& p) -> Eigen::Vector2d {
    if (p.crossing < 0) return q.z[p.corner];
    const Crossing& x = crossings_[p.crossing];
    const auto [i, j] = ends_of(x);
    const double bi = (1 - x.t) * q.w[i], bj = x.t * q.w[j];
    return (bi * q.z[i] + bj * q.z[j]) / (bi + bj);
  };
  auto s_of = [&](const Point& p, int E) -> double {
    if (p.crossing >= 0) return crossings_[p.crossing].s;
    return p.vertex == input_.edge_vertices(E)[0] ? 0.0 : 1.0;
  };

  // Where each strand's ends lie on the boundary k -> a -> l (side A) and k -> b -> l (side B).
  struct End {
    char side = 0;  // 'A', 'B', 'K', 'L'
    double pos = 0;
  };
  // Parameter of crossing c from the head of side h (b -> k, l -> b: from k, from b).
  auto t_to_head = [&](int crossing, int side) {
    const double t = crossings_[crossing].t;
    return runs_from_tail(side) ? 1 - t : t;
  };
  auto end_of = [&](const Point& p) -> End {
    if (p.crossing < 0) {
      if (p.corner == K) return {'K', 0};
      if (p.corner == L) return {'L', 0};
      return {p.corner == A ? 'A' : 'B', 1};
    }
    const Crossing& x = crossings_[p.crossing];
    if (x.edge == q.e_ka) return {'A', t_along(p.crossing, q.h_ka)};
    if (x.edge == q.e_al) return {'A', 1 + t_along(p.crossing, q.h_al)};
    if (x.edge == q.e_bk) return {'B', t_to_head(p.crossing, q.h_bk)};
    if (x.edge == q.e_lb) return {'B', 1 + t_to_head(p.crossing, q.h_lb)};
    return {0, 0};
  };

  std::vector<Strand> strands = strands_through(q);
  struct Cut {
    size_t strand;
    double pos_a, pos_b;
    bool from_a;     // the strand runs from side A to side B
    double t_k = 0;  // along the new edge from k (convention)
    double s = 0;    // along the input edge
  };
  std::vector<Cut> cuts;
  std::vector<int> coinciding;  // strands from k to l: input edges that become the new edge
  for (size_t i = 0; i < strands.size(); ++i) {
    const End e0 = end_of(strands[i].p0), e1 = end_of(strands[i].p1);
    if (!e0.side || !e1.side) fail("a strand leaves the quadrilateral through no side");
    if ((e0.side == 'K' && e1.side == 'L') || (e0.side == 'L' && e1.side == 'K')) {
      coinciding.push_back(static_cast<int>(i));
    } else if ((e0.side == 'A' && e1.side == 'B') || (e0.side == 'B' && e1.side == 'A')) {
      const bool from_a = e0.side == 'A';
      cuts.push_back({i, from_a ? e0.pos : e1.pos, from_a ? e1.pos : e0.pos, from_a});
    }
  }
  if (!coinciding.empty() && (coinciding.size() > 1 || !cuts.empty())) {
    fail("an input edge from k to l and other strands cross the new diagonal");
  }
  std::sort(cuts.begin(), cuts.end(), [](const Cut& x, const Cut& y) {
    return x.pos_a != y.pos_a ? x.pos_a < y.pos_a : x.pos_b < y.pos_b;
  });

  // Geometry of each cut: where the strand's polyline meets the segment k-l.
  const Eigen::Vector2d zk = q.z[K], zl = q.z[L], kl = zl - zk;
  for (Cut& cut : cuts) {
    const Strand& st = strands[cut.strand];
    // The strand's polyline: its ends and the crossing between them, if any (on the stack: a flip
    // has a cut per input edge crossing the new diagonal, and many flips build a subdivision).
    std::array<Point, 3> pts = {st.p0, st.p1, st.p1};
    size_t num_pts = 2;
    if (st.m >= 0) pts[1] = {st.m, -1, -1}, num_pts = 3;
    std::array<Eigen::Vector2d, 3> zs;
    std::array<double, 3> side{};
    for (size_t i = 0; i < num_pts; ++i) {
      zs[i] = place(pts[i]);
      side[i] = cross(kl, zs[i] - zk);
    }
    // The first segment whose ends lie on opposite sides of the line k-l (the ends of the strand
    // do, combinatorially; in rounding the middle point may sit on the line).
    size_t seg = 0;
    for (; seg + 1 < num_pts; ++seg) {
      if ((side[seg] > 0) != (side[seg + 1] > 0)) break;
    }
    if (seg + 1 >= num_pts) seg = 0;
    const double d0 = side[seg], d1 = side[seg + 1];
    const double sigma = d0 != d1 ? std::clamp(d0 / (d0 - d1), 0.0, 1.0) : 0.5;
    const Eigen::Vector2d x = zs[seg] + sigma * (zs[seg + 1] - zs[seg]);
    const double tau = std::clamp((x - zk).dot(kl) / kl.squaredNorm(), 0.0, 1.0);
    const double bk_ = (1 - tau) / q.w[K], bl_ = tau / q.w[L];
    cut.t_k = bl_ / (bk_ + bl_);
    const int E = st.input_edge;
    const Point &P = pts[seg], &Q = pts[seg + 1];
    const double sp = s_of(P, E), sq = s_of(Q, E);
    if (q.circle && projective_ && (P.crossing >= 0 || Q.crossing >= 0)) {
      // The input edge is the chord of the circle between its two ideal vertices; its parameter
      // is projective along it, fixed by one point of known s.
      const Eigen::Vector2d zp = zs[seg], dz = zs[seg + 1] - zs[seg];
      const double qa = dz.squaredNorm(), qb = 2 * zp.dot(dz), qc = zp.squaredNorm() - 1;
      const double disc = std::sqrt(std::max(0.0, qb * qb - 4 * qa * qc));
      const double mu0 = (-qb - disc) / (2 * qa), mu1 = (-qb + disc) / (2 * qa);
      auto along = [&](double mu) { return (mu - mu0) / (mu1 - mu0); };
      const bool use_p = P.crossing >= 0;
      const double x_ref = along(use_p ? 0.0 : 1.0), s_ref = use_p ? sp : sq;
      const double rho = (s_ref / (1 - s_ref)) / (x_ref / (1 - x_ref));
      const double xx = along(sigma);
      const double odds = rho * xx / (1 - xx);
      cut.s = odds / (1 + odds);
    } else if (q.circle && P.crossing < 0 && Q.crossing < 0) {
      // The diagonal a-b itself: the picture's parameter turned into the convention's by the
      // weights, as for the new edge's below.
      const double bp = (1 - sigma) / q.w[P.corner], bq = sigma / q.w[Q.corner];
      cut.s = sp + (sq - sp) * bq / (bp + bq);
    } else {
      cut.s = sp + sigma * (sq - sp);
    }
    // Strictly between its neighbours along the input edge.
    const double lo = s_of(st.p0, E), hi = s_of(st.p1, E);
    if (!(cut.s > lo && cut.s < hi) || !std::isfinite(cut.s)) cut.s = 0.5 * (lo + hi);
  }
  // Strictly increasing along k-l, in the combinatorial order.
  for (size_t i = 0; i < cuts.size(); ++i) {
    double lo = i == 0 ? 0.0 : cuts[i - 1].t_k;
    if (!(cuts[i].t_k > lo) || !(cuts[i].t_k < 1) || !std::isfinite(cuts[i].t_k)) {
      // Spread the remaining ones evenly between lo and 1 when rounding left no room.
      const size_t rest = cuts.size() - i;
      for (size_t j = 0; j < rest; ++j) {
        const double want =
            lo + (1 - lo) * static_cast<double>(j + 1) / static_cast<double>(rest + 1);
        if (!(cuts[i + j].t_k > (j == 0 ? lo : cuts[i + j - 1].t_k)) || !(cuts[i + j].t_k < 1) ||
            !std::isfinite(cuts[i + j].t_k)) {
          cuts[i + j].t_k = want;
        }
      }
    }
  }

  // The flip itself, then the new crossings and the strands' new links.
  for (int x : on_edge_[e]) {
    crossings_[x].alive = false;
    free_.push_back(x);
  }
  on_edge_[e].clear();
  const int was_coincident = coincident_[e];
  coincident_[e] = -1;
  if (!current_.flip(e)) fail("the edge cannot be flipped");
  // The new edge in g = (l, b, k), opposite b: the halfedge k -> l.
  const bool k_first = runs_from_tail(3 * q.g + 1);
  auto link = [&](int E, const Point& from, int to_crossing, const Point& to) {
    // from -> to_crossing (or to, when to_crossing < 0)
    const int next = to_crossing >= 0 ? to_crossing : to.crossing;
    if (from.crossing >= 0) {
      crossings_[from.crossing].next = next;
    } else {
      first_[E] = next;
    }
    if (next >= 0) crossings_[next].prev = from.crossing;
  };
  std::vector<char> cut_strand(strands.size(), 0);
  for (const Cut& cut : cuts) {
    const Strand& st = strands[cut.strand];
    cut_strand[cut.strand] = 1;
    Crossing x;
    x.input_edge = st.input_edge;
    x.edge = e;
    x.t = k_first ? cut.t_k : 1 - cut.t_k;
    x.s = cut.s;
    x.forward = cut.from_a;  // side A is face f = edge_faces(e)[0] after the flip
    x.prev = st.p0.crossing;
    x.next = st.p1.crossing;
    const int id = add_crossing(x);
    on_edge_[e].push_back(id);
    link(st.input_edge, st.p0, id, st.p1);
    if (st.p1.crossing >= 0) crossings_[st.p1.crossing].prev = id;
  }
  for (size_t i = 0; i < strands.size(); ++i) {
    if (cut_strand[i]) continue;
    const Strand& st = strands[i];
    if (st.m < 0 && st.p0.crossing < 0 && st.p1.crossing < 0) {
      if (st.input_edge == was_coincident) fail("the flipped input edge does not cross k-l");
      continue;
    }
    link(st.input_edge, st.p0, -1, st.p1);
  }
  for (int i : coinciding) coincident_[e] = strands[static_cast<size_t>(i)].input_edge;
  ++num_flips_;
}

}  // namespace ricci::detail
