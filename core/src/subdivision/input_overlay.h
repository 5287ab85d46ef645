// The input's edges followed through the flow's edge flips: where each input edge crosses the
// edges of the current triangulation, kept up to date flip by flip (an overlay of the two
// triangulations, in the spirit of Campen et al. 2021 and of the normal coordinates of Gillespie,
// Sharp and Crane 2021, written for this project). The common subdivision
// (common_subdivision.h) is read off the overlay after the last flip.
//
// A crossing has a parameter on each of its two edges: t on the current edge, s on the input
// edge, both barycentric coordinates of the edge's second vertex. Two conventions:
//   projective (every flip kept the discrete conformal class: Yamabe, Ptolemy flips, after any
//     isometric flips of the input's metric, EdgeFlip::isometric, drawn unfolded): t and s are
//     barycentric coordinates in the triangles of the lambda-lengths (u = 0). With the conformal
//     factor u, a triangle's points move by the projective map that keeps its circumcircle, which
//     in barycentric coordinates is b_v -> b_v e^(-u_v), normalized (Springborn, Schroeder,
//     Pinkall 2008); input edges and flipped edges are then geodesics of one hyperbolic surface
//     (Penner), straight in every triangle, and the map is the piecewise projective one of
//     Gillespie, Springborn and Crane 2021.
//   frozen (some flip kept the metric of its moment: the packing schemes, mixed): a crossing is
//     made where the new diagonal meets the input edge in the metric of that moment, and keeps its
//     barycentric coordinates as u changes afterwards: each triangle moves by the affine map
//     between its realizations, so crossings keep their order along every edge and segments stay
//     straight inside every triangle, and the overlay stays an embedding (a bijection).
// In both, an input edge inside a triangle is a straight chord between its crossings; a flip
// computes the new crossings in a planar picture of the quadrilateral where all of them are
// straight (the circle through its four vertices in the projective case, the unfolded pair of
// triangles otherwise), and their order along the new edge combinatorially, from where the
// strands enter and leave the quadrilateral, so rounding can never make two input edges cross.
#pragma once

#include <vector>

#include "ricci/flow/flow_result.h"
#include "ricci/mesh/triangulation.h"

namespace ricci::detail {

struct Crossing {
  int input_edge = -1;
  int edge = -1;             //!< of the current triangulation
  double t = 0;              //!< along `edge`, from its edge_vertices()[0] (runs_from_tail)
  double s = 0;              //!< along the input edge, from its edge_vertices()[0]
  int prev = -1, next = -1;  //!< along the input edge; -1: its first (last) vertex
  bool forward = true;       //!< the input edge passes from edge_faces(edge)[0] to [1]
  bool alive = true;
};

class InputOverlay {
 public:
  //! \param projective the convention above; true when every flip will be a Ptolemy flip.
  InputOverlay(const Triangulation& input, bool projective);

  //! Flips record.edge of the current triangulation and follows the input's edges through it.
  //! \throws LayoutError when a strand cannot be followed (names the flip).
  void flip(const EdgeFlip& record);

  const Triangulation& input() const { return input_; }
  const IntrinsicTriangulation& triangulation() const { return current_; }
  bool projective() const { return projective_; }
  const std::vector<Crossing>& crossings() const { return crossings_; }
  //! Live crossings on an edge of the current triangulation, in the order of t.
  std::vector<int> crossings_on(int edge) const;
  //! The input edge that runs along current edge e, or -1.
  int coincident_input_edge(int e) const { return coincident_[e]; }
  //! The first crossing of input edge E from its edge_vertices()[0], or -1 (none: it is an edge
  //! of the current triangulation).
  int first_crossing(int input_edge) const { return first_[input_edge]; }
  int num_flips() const { return num_flips_; }

  //! Whether the parameters t of the crossings on halfedge h's edge run from h's tail (else from
  //! its head): from the edge's edge_vertices()[0], and on a loop (an edge from a vertex to
  //! itself) from the tail of its halfedge in edge_faces()[0].
  bool runs_from_tail(int h) const;
  //! Parameter of crossing c measured from the tail of halfedge h of its current edge.
  double t_along(int c, int h) const;
  //! Parameter of crossing c on side `side` of face `face` of the current triangulation (from
  //! corner `side` to corner side + 1), measured from corner `side`.
  double t_on_side(int c, int face, int side) const {
    return t_along(c, side_halfedge(face, side));
  }
  //! The halfedge of face `face` from corner `side` to corner side + 1.
  static int side_halfedge(int face, int side) { return 3 * face + (side + 2) % 3; }

 private:
  struct Point;
  struct Strand;
  struct Quad;
  std::vector<Strand> strands_through(const Quad& q) const;
  int add_crossing(const Crossing& c);

  const Triangulation& input_;
  IntrinsicTriangulation current_;
  bool projective_;
  std::vector<Crossing> crossings_;
  std::vector<int> free_;                  // dead crossing slots
  std::vector<std::vector<int>> on_edge_;  // per current edge
  std::vector<int> coincident_;            // per current edge
  std::vector<int> first_;                 // per input edge
  int num_flips_ = 0;
};

}  // namespace ricci::detail
