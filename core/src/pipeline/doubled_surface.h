// Edge flips across the boundary: the flow on the double of a surface with boundary
// (CompactMesh::doubled), as Campen, Capouellez, Shen, Zhu, Panozzo and Zorin 2021 do for
// discrete conformal maps with boundary (written for this project). On the double every edge is
// interior, so the Ptolemy flips of the Euclidean Yamabe flow reach a valid triangulation at every
// u (Springborn 2020), and the Delaunay flips of the hyperbolic one reach boundary edges too. The
// double's target and metric are symmetric under the reflection that swaps the two copies; the
// reflection's fixed set, the original boundary, is then a geodesic between boundary vertices, and
// the half is a flat (hyperbolic) surface whose boundary is straight (geodesic) between its
// vertices, with angle sums half the double's there.
//
// The half's own faces are not triangles of the final metric (that is why the flow needed the
// double, or why the half's own class was not the double's), so what is delivered is always the
// common subdivision: the pieces of the double's common subdivision that lie in the half's faces,
// developed in the plane piece by piece (cut open on the input's edges where the half is no
// disk).
// (Not installed API.)
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pipeline/half_subdivision.h"
#include "ricci/flow/flow_result.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/pipeline/uniformization.h"
#include "ricci/subdivision/common_subdivision.h"

namespace ricci::detail {

//! Whether a flow of `run` (its scheme, geometry and preset) that stalls at the boundary's
//! triangles is repeated on the double: a Yamabe flow on a surface with boundary laid out in the
//! plane (E2) or the Poincare disk (H2), a curvature target at every vertex (or the atlas), flips
//! allowed.
bool double_follows_boundary_stall(const CompactMesh& half, const UniformizationOptions& options,
                                   const TargetCurvature& target, const Uniformization& run);

//! Whether the flow of `run` is repeated on the double: double_follows_boundary_stall, its flow
//! stopped by triangles at the boundary, and no flow on the double failed for it before
//! (run.double_failure).
bool may_flow_on_double(const CompactMesh& half, const UniformizationOptions& options,
                        const TargetCurvature& target, const Uniformization& run);

//! Why the converged flow of `run` is not in the canonical discrete conformal class of the
//! surface, its double's, or "" when it is or the double is not tried. On a surface with boundary
//! the canonical class is that of its double (Gillespie, Springborn and Crane 2021; CEPS flows
//! there), where boundary edges flip too. Tried for a Euclidean Yamabe flow that converged with
//! edge flips, laid out in the plane (one disk or cut open), the canonical class asked for, the
//! input's triangulation not kept, not the disk preset (whose circle fit repeats flows) nor the
//! atlas (measured: no better on the whole, at up to 3.5 times the time), u not 0 everywhere (at u
//! = 0 every class's metric is the input's); a flow that needed no flip keeps the input's class, as
//! on closed surfaces. The classes differ where the flow converged only in the input
//! triangulation's class (the canonical one stalled at the boundary), or where a boundary edge
//! faces an angle above a right angle in the half's intrinsic Delaunay triangulation of the input
//! metric (where its class starts) or in its final one: the double's Delaunay triangulation flips
//! such an edge.
std::string class_other_than_doubles(const CompactMesh& half, const UniformizationOptions& options,
                                     const Uniformization& run);

//! Kbar on the double: the half's at its vertices and at their copies, twice the half's at its
//! boundary vertices (a boundary angle sum theta is 2 theta on the double: K = 2 pi - 2 theta
//! = 2 (pi - theta)); held fixed where the half's is.
TargetCurvature doubled_target(const CompactMesh& half, const CompactMesh& twice,
                               const TargetCurvature& target);

//! The half's part of the double's flow result: u, K, Kbar and radii at the half's vertices, K
//! and Kbar halved at the boundary; counts and histories as they are. No edge lengths and no
//! triangulation: the half's faces are not triangles of the final metric.
FlowResult half_result(const CompactMesh& half, const FlowResult& twice);

//! Each face of the triangulation drawn by itself from its lengths (corner 0 at the origin,
//! corner 1 on the positive x axis), in the plane or the Poincare disk: a layout whose faces are
//! the final metric's triangles but are not glued, which is all the common subdivision needs.
Layout face_by_face_layout(const Triangulation& mesh, Geometry geometry,
                           const std::vector<double>& lengths);

//! The lengths of the half's boundary edges in the final metric of a converged flow on its double
//! (0 at the other edges): each is an edge of the double's input and a geodesic of its final
//! metric (the reflection's fixed set), straight through the final faces the overlay of the
//! flips says it crosses, so the distance between its ends with those faces unfolded. What the
//! half's common subdivision measures (HalfSubdivision::boundary_lengths) without making it; empty
//! where the crossed faces do not unfold as such a strip.
std::vector<double> boundary_lengths_on_double(const CompactMesh& half, const CompactMesh& twice,
                                               const FlowResult& result);

//! The flow of `run` repeated on the double (the disk preset's flows included), and its result
//! put in `run` for the half: result, totals (the half's own flow counted too), the subdivision
//! and its layout, `doubled`, and `doubled_because` (run.result.failure as it came in); returns
//! "". When the flow on the double does not converge or its pieces give no layout, leaves `run`
//! as it was but for the double's totals, and returns why ("on the surface doubled ...").
std::string flow_on_double(const CompactMesh& half, const UniformizationOptions& options,
                           int outer_loop, const TargetCurvature& target, Uniformization& run);

}  // namespace ricci::detail
