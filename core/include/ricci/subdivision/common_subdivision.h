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
// the input's edges, and cut into triangles (PieceTriangles). The new vertices then also include
// the crossings of Tb's and Tc's edges, inside input faces (vertex_input_edge -1, at their
// barycentric coordinates there); one nearer to an input edge's crossing on the same edge of Tb
// than float texture coordinates resolve is that vertex. The other flows (H2, S2, frozen metrics,
// no isometric flips) follow the input's edges through all flips in one overlay.
//
// Vertices: the input's first, unchanged and in order; then one per crossing of an input edge with
// an edge of T', input edge after input edge, in the order along each (through Tb: with Tb's
// edges too, then the crossings of Tb's and Tc's edges inside input faces). The Poincare disk's
// drawing may split sides further (disk_drawing.h): those vertices come last, each on its side
// (dividing it as the split divides the geodesic), on an input edge or inside an input face.
#pragma once

#include "ricci/flow/flow_result.h"
#include "ricci/flow/scheme.h"
#include "ricci/layout/layout.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/subdivision/subdivided_mesh.h"

namespace ricci {

//! Builds the common subdivision of a converged flow with flips. `initial` is the conformal
//! structure the flow started from, `layout` the layout of result_triangulation(mesh, result);
//! `how` cuts the pieces of more than three corners into triangles in the plane (the Poincare
//! disk's and the sphere's pieces on the route of one overlay are fans from their first corner).
//! \throws LayoutError when the input's edges cannot be followed through the flips consistently
//!   (names the flip or face).
CommonSubdivision common_subdivision(const CompactMesh& mesh, const ConformalStructure& initial,
                                     const FlowResult& result, const Layout& layout,
                                     DiskSidePoints disk_points = DiskSidePoints::OnGeodesic,
                                     PieceTriangles how = PieceTriangles::NearestToConformal);

}  // namespace ricci
