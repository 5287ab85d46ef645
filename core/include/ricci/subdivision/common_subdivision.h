// The common subdivision of the input mesh and the flow's final triangulation: what a flow that
// flipped edges delivers when the input's own faces, drawn by their corners, would turn over.
//
// The flow's metric lives on the flipped triangulation T' of the input's vertices; the input's
// edges, followed through every flip (input_overlay.h), cross the edges of T'. Cutting the input
// mesh along T' (equivalently T' along the input's edges) gives pieces that each lie in one input
// face, so the result is the user's surface exactly (new vertices lie on input edges, or through
// Tb below inside input faces, at their 3D position), and in one face of T', so each piece's layout
// is a straight piece of a triangle of the final metric: in the plane, the Poincare disk or on the
// sphere. Pieces are convex in both, and fan-triangulated. A new vertex is the same point of the
// surface in 3D and in the layout: the point of the flow's discrete conformal map
// (input_overlay.h), on the geodesic side of its final face (in the Poincare disk an arc: its
// copies on the two sides of a cut are images of each other under the deck transformation, and the
// pieces are hyperbolic triangles; drawn with straight sides, thin ones near the rim can turn over,
// which disk_drawing.h mends).
//
// The Euclidean Yamabe flow with flips first flips the input Ta isometrically to its intrinsic
// Delaunay triangulation Tb, then by Ptolemy flips to the final Tc = T'; the map is projective on
// the cells of all three only, so its pieces are Ta, Tb and Tc cut by each other: Tb's faces cut
// by Tc (the Ptolemy flips followed over Tb), each piece cut in its Tb face's Euclidean chart by
// the input's edges, and triangulated by ears. The new vertices then also include the crossings
// of Tb's and Tc's edges, inside input faces (vertex_input_edge -1, at their barycentric
// coordinates there); one nearer to an input edge's crossing on the same edge of Tb than float
// texture coordinates resolve is that vertex. The other flows (H2, S2, frozen metrics, no
// isometric flips) follow the input's edges through all flips in one overlay.
//
// Vertices: the input's first, unchanged and in order; then one per crossing of an input edge with
// an edge of T', input edge after input edge, in the order along each (through Tb: with Tb's
// edges too, then the crossings of Tb's and Tc's edges inside input faces). The Poincare disk's
// drawing may split sides further (disk_drawing.h): those vertices come last, each on its side
// (dividing it as the split divides the geodesic), on an input edge or inside an input face.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/flow_result.h"
#include "ricci/flow/scheme.h"
#include "ricci/layout/layout.h"
#include "ricci/mesh/compact_mesh.h"

namespace ricci {

struct CommonSubdivision {
  int num_input_vertices = 0;
  std::vector<Eigen::Vector3d> positions;  //!< 3D, on the input surface
  std::vector<std::array<int, 3>> faces;   //!< oriented as the input's
  std::vector<int> input_face;             //!< per face: the input face it lies in
  std::vector<int> final_face;             //!< per face: the face of T' it lies in
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

//! Builds the common subdivision of a converged flow with flips. `initial` is the conformal
//! structure the flow started from, `layout` the layout of result_triangulation(mesh, result).
//! \throws LayoutError when the input's edges cannot be followed through the flips consistently
//!   (names the flip or face).
CommonSubdivision common_subdivision(const CompactMesh& mesh, const ConformalStructure& initial,
                                     const FlowResult& result, const Layout& layout,
                                     DiskSidePoints disk_points = DiskSidePoints::OnGeodesic);

}  // namespace ricci
