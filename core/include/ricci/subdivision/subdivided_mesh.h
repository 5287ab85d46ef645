// The common subdivision as delivered (common_subdivision.h builds it): the pieces, their 3D
// positions on the input surface, their layout, and where each lies in the input and the flow's
// final triangulation.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

namespace ricci {

struct CommonSubdivision {
  int num_input_vertices = 0;
  std::vector<Eigen::Vector3d> positions;  //!< 3D, on the input surface
  std::vector<std::array<int, 3>> faces;   //!< oriented as the input's
  std::vector<int> input_face;             //!< per face: the input face it lies in
  //! Per face: the face of T' it lies in; -1 for an input face kept whole (an atlas with some
  //! faces cut into their pieces: pipeline/texture_atlas.h).
  std::vector<int> final_face;
  //! Per face: its chart where the layout is in several (Layout::chart) and the faces are not
  //! those of T' (the half of a doubled surface); empty otherwise.
  std::vector<int> chart;
  //! Per vertex: an input face holding it and its barycentric coordinates there (for the input's
  //! vertices: a face of theirs, with a unit coordinate).
  std::vector<int> vertex_input_face;
  std::vector<Eigen::Vector3d> vertex_barycentric;
  //! Per new vertex: the input edge it lies on and its parameter there (0 at the edge's first
  //! vertex, 1 at its second); -1 and NaN for a vertex inside an input face (a side split for the
  //! Poincare disk's drawing, or a crossing of Tb's and Tc's edges).
  std::vector<int> vertex_input_edge;
  std::vector<double> vertex_edge_parameter;
  //! The layout per face and corner, in the model of `layout` (before any normalization), as
  //! drawn: a texture draws it with straight sides.
  std::vector<std::array<Eigen::Vector3d, 3>> corners;
  //! H2 where new vertices were moved onto their faces' sides as drawn (drawn_side_corners,
  //! on_drawn_sides): per face and corner as `corners`, every vertex at its point of the
  //! conformal map, on the geodesics (hyperbolic triangles, whose copies across a cut are images
  //! of each other under the deck transformations). Empty otherwise: `corners` are those.
  std::vector<std::array<Eigen::Vector3d, 3>> model_corners;
  //! Per vertex: its position in the layout from the first face that holds it (H2 in charts: in
  //! that face's chart).
  std::vector<Eigen::Vector3d> vertex_layout;
  //! Per vertex: u, the input's for input vertices, interpolated along the input edge for new
  //! ones (for a vertex of a split side, interpolated along the side).
  Eigen::VectorXd u;
  int num_flips = 0;  //!< flips followed
  //! Sides split on their geodesics so that faces near the Poincare disk's rim keep their
  //! orientation drawn straight (each adds one vertex).
  int disk_splits = 0;
  //! H2: new vertices on their final faces' sides as drawn (DiskSidePoints::OnDrawnSide), all of
  //! them, or at drawn_side_corners corners, those of the final faces whose pieces turned over
  //! as drawn on the geodesics.
  bool on_drawn_sides = false;
  int drawn_side_corners = 0;
  double seconds = 0;  //!< time to build it
};

//! Where a new vertex goes in the Poincare disk: onto the geodesic side of its final face (the
//! point of the metric: copies across a cut glue), or onto that side as drawn, straight in the
//! disk's coordinates (pieces then stay inside their drawn face, where splitting the geodesic
//! pieces cannot keep every thin one near a chart's rim from turning over as drawn).
enum class DiskSidePoints { OnGeodesic, OnDrawnSide };

//! The triangles a piece of more than three corners is cut into: those whose affine maps from the
//! input face to the layout are nearest to conformal, none turned over as drawn where a
//! triangulation allows (the layout delivered as drawn), or the roundest in the input face (the
//! pieces' insides drawn again, as an atlas's charts are by a harmonic map, whose cotangent
//! weights needles spoil).
enum class PieceTriangles { NearestToConformal, Roundest };

}  // namespace ricci
