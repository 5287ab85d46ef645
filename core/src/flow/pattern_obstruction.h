// A necessary condition for circle patterns with prescribed intersection angles (Thurston's
// condition on a vertex's link): the angle at a vertex whose circle meets its neighbours' at
// angles Phi stays below sum (pi - Phi) over the link edges, the limit as its circle shrinks to a
// point. A target angle sum at or above that bound has no solution; Newton's method then drives
// the radius to 0 and the residual to 0 with it, a degenerate pattern that is not a solution.
#pragma once

#include <string>

#include "ricci/flow/scheme.h"
#include "ricci/flow/target.h"
#include "ricci/mesh/triangulation.h"

namespace ricci {

//! Checks every vertex with a curvature target whose circle and neighbours' circles are real
//! (eps = +1) and meet at angles in [0, pi/2] (0 <= eta <= 1): the target angle sum 2 pi - Kbar
//! (pi - Kbar on the boundary) must be below sum over its triangles of (pi - acos(eta_ab)), eta_ab
//! on the edge opposite the vertex. Returns "" when it holds, else a message naming the first
//! vertex that violates it, how many do, and what to change.
std::string circle_pattern_obstruction(const Triangulation& mesh,
                                       const ConformalStructure& structure,
                                       const TargetCurvature& target);

}  // namespace ricci
