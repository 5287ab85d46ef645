// Straight drawings of hyperbolic triangles in the Poincare disk (not installed API).
//
// A texture draws each face's sides straight in the disk's coordinates, but the sides of a
// hyperbolic triangle are geodesics: circular arcs that bow toward the disk's centre. Near the rim
// a thin triangle whose third corner lies between a side's chord and its arc is positive as a
// hyperbolic triangle (its Klein-model drawing, where geodesics are straight, keeps the
// orientation) and turned over as drawn. Halving that side at its geodesic midpoint quarters the
// bow of each half against its length, so a few rounds of halving give a drawing with every face
// positive; a cap, whose third corner lies close to the arc, is split at the foot of the
// perpendicular from it instead (its halves meet there and are drawn positive). The new vertex
// divides the side in 3D as it divides the geodesic, on the user's surface, so the delivered mesh
// is a subdivision of the input like the common subdivision.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/flow_result.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/subdivision/common_subdivision.h"

namespace ricci::detail {

//! The input mesh as its own common subdivision: its faces (each its own input and final face),
//! their layout corners, u, and no new vertex.
CommonSubdivision input_as_subdivision(const CompactMesh& mesh, const FlowResult& result,
                                       const std::vector<std::array<Eigen::Vector3d, 3>>& corners);

//! Whether some face of a Poincare-disk drawing is turned over as drawn while positive in the
//! Klein model (what split_turned_disk_faces mends).
bool has_drawing_turned_faces(const std::vector<std::array<Eigen::Vector3d, 3>>& corners);

//! Round after round, splits the longest drawn side of every face that is turned over as drawn
//! (beyond what rounding decides) but positive in the Klein model, on its geodesic: at the midpoint
//! when every half on that side is then drawn positive, else at the foot of the perpendicular from
//! the face's third corner (a cap) when that leaves fewer halves turned. The new vertex divides the
//! side in 3D as it divides the geodesic's length, and every face on that side is split (one side
//! per face and round). A new vertex gets its input face, its barycentric coordinates there and
//! its input edge where it lies on one (else -1), u interpolated along the side. Keeps the best
//! state seen; stops when no such face is left, after max_rounds, after 20 rounds without
//! progress, or when such faces grow far past their first number. Faces turned in the Klein model
//! too are left as they are. Where the subdivision has model_corners, they are split alike: the
//! new vertex on the model's geodesic at the fraction of its length at which it divides the side
//! in 3D. Returns the number of sides split.
int split_turned_disk_faces(const CompactMesh& mesh, CommonSubdivision& sub, int max_rounds = 60);

//! Per face of the flow's final triangulation: whether a face of the subdivision in it is turned
//! over as drawn but positive in the Klein model.
std::vector<char> final_faces_turned_as_drawn(const CommonSubdivision& sub, int num_final_faces);

//! A subdivision with its new vertices on the geodesics (before any split): the new vertices on
//! the sides of the marked final faces go onto those sides as drawn, straight in the disk's
//! coordinates, at every corner of theirs (the neighbour across an uncut side draws it alike;
//! across a cut the two drawn copies then no longer glue exactly). The corners before the move are
//! kept as the subdivision's model_corners (unless it has them), where they do. Returns the
//! corners moved.
int draw_sides_straight(CommonSubdivision& sub, const Layout& layout,
                        const std::vector<char>& final_faces);

}  // namespace ricci::detail
