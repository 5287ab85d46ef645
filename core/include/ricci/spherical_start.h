// A starting point for the spherical Yamabe flow of a closed genus-0 surface: the Euclidean flow
// of the mesh punctured at one vertex, laid out in the plane and lifted to the unit sphere by
// inverse stereographic projection (Springborn, Schroeder, Pinkall; Gillespie, Springborn, Crane).
#pragma once

#include <Eigen/Core>

#include "ricci/compact_mesh.h"
#include "ricci/scheme.h"

namespace ricci {

//! Conformal factors for the S2 Yamabe structure `structure` (eps = 0 everywhere) that
//! approximate the round-sphere metric: the punctured mesh is flattened (Euclidean Yamabe flow
//! with edge flips, u on the puncture's link fixed so that the removed star becomes the
//! neighbourhood of infinity), laid out, centred and scaled, lifted to the sphere, and u is the
//! least-squares fit of the lifted edge lengths.
//! \pre mesh is a closed genus-0 surface, structure.geometry is S2 with every eps 0.
//! \throws ConvergenceError when the punctured flow does not converge.
Eigen::VectorXd stereographic_start(const CompactMesh& mesh, const ConformalStructure& structure);

}  // namespace ricci
