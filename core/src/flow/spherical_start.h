// A starting point for the spherical flow of a closed genus-0 surface, in every scheme: the
// Euclidean flow of the mesh punctured at one vertex, laid out in the plane and lifted to the unit
// sphere by inverse stereographic projection (Springborn, Schroeder, Pinkall; Gillespie,
// Springborn, Crane). Inversive distances, and so each scheme's eta, are invariant under the
// Moebius maps, which is why the lift of the flat pattern is close to the round one.
#pragma once

#include <optional>

#include <Eigen/Core>

#include "ricci/flow/flow_result.h"
#include "ricci/flow/scheme.h"
#include "ricci/flow/target.h"
#include "ricci/linear/vertex_order.h"
#include "ricci/mesh/compact_mesh.h"

namespace ricci {

//! Conformal factors for the S2 structure `structure` (on mesh's own triangulation) that
//! approximate the round-sphere metric: the punctured mesh is flattened (the Euclidean flow of the
//! same eps and radii with edge flips, u on the puncture's link fixed so that the removed star
//! becomes the neighbourhood of infinity), laid out, centred and scaled, and lifted to the sphere;
//! each vertex's u is scaled by the projection's conformal factor, and the puncture's u is the best
//! fit of its lifted edge lengths.
//! \pre mesh is a closed genus-0 surface, structure.geometry is S2.
//! `order`, a fill-reducing order of the mesh's vertices (VertexOrder), orders the punctured flow
//! on the mesh's own triangulation and the final fit instead of an ordering of their own.
//! \throws ConvergenceError when the punctured flow does not converge.
Eigen::VectorXd stereographic_start(const CompactMesh& mesh, const ConformalStructure& structure,
                                    const VertexOrder& order = {});

//! Where the flow to `target` walks before Newton: the stereographic start on a closed genus-0
//! surface in S2 with a curvature target at every vertex (when options.stereographic_start and a
//! puncture flattened); otherwise none.
std::optional<Eigen::VectorXd> flow_start(const CompactMesh& mesh,
                                          const ConformalStructure& structure,
                                          const TargetCurvature& target, const FlowOptions& options,
                                          const VertexOrder& order = {});

}  // namespace ricci
