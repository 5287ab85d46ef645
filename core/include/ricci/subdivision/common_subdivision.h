// The common subdivision of the input mesh and the flow's final triangulation: what a flow that
// flipped edges delivers when the input's own faces, drawn by their corners, would turn over.
//
// The flow's metric lives on the flipped triangulation T' of the input's vertices; the input's
// edges, followed through every flip (input_overlay.h), cross the edges of T'. Cutting the input
// mesh along T' (equivalently T' along the input's edges) gives pieces that each lie in one input
// face, so the result is the user's surface exactly (new vertices lie on input edges, at their
// 3D position), and in one face of T', so each piece's layout is a straight piece of a triangle
// of the final metric: in the plane, the Poincare disk or on the sphere. Pieces are convex in
// both, and fan-triangulated.
//
// Vertices: the input's first, unchanged and in order; then one per crossing of an input edge with
// an edge of T', input edge after input edge, in the order along each. The Poincare disk's
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
  //! Poincare disk's drawing).
  std::vector<int> vertex_input_edge;
  std::vector<double> vertex_edge_parameter;
  //! The layout per face and corner, in the model of `layout` (before any normalization).
  std::vector<std::array<Eigen::Vector3d, 3>> corners;
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
  double seconds = 0;  //!< time to build it
};

//! Where a new vertex goes in the Poincare disk: onto the side of its final face as the layout
//! draws it, straight in the disk's coordinates (so pieces stay inside their drawn face), or onto
//! the geodesic itself (the point of the metric, for a caller that develops the pieces again).
enum class DiskSidePoints { OnDrawnSide, OnGeodesic };

//! Builds the common subdivision of a converged flow with flips. `initial` is the conformal
//! structure the flow started from, `layout` the layout of result_triangulation(mesh, result).
//! \throws LayoutError when the input's edges cannot be followed through the flips consistently
//!   (names the flip or face).
CommonSubdivision common_subdivision(const CompactMesh& mesh, const ConformalStructure& initial,
                                     const FlowResult& result, const Layout& layout,
                                     DiskSidePoints disk_points = DiskSidePoints::OnDrawnSide);

}  // namespace ricci
