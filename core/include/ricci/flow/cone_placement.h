// Cone singularities for a flat metric of bounded area distortion, placed on the linear model of
// the Euclidean Yamabe flow (ATLAS.md, "One model under all of them").
//
// At u = 0 the flow's curvature is K(u) ~ K0 + H u, with H the Hessian of the input metric's
// intrinsic Delaunay triangulation (the cotangent Laplacian, positive semi-definite there). A cone
// set C with u held at 0 there, flat elsewhere and u = 0 on the boundary, gives
//   u = g + G_C k + c 1,   g = R(-K0),  G_C = R(e_C),
// where R solves H u = b over the free vertices (one pinned on a closed surface) and k are the
// cones' curvatures: u_C = 0 and, on a closed surface, sum k = 2 pi chi fix k and c by a dense
// (|C| + 1) system. H is factored once; each cone tried costs one back-solve (its column of G),
// whatever the set it is tried in, and D of a set is a quadratic form in k over the columns'
// area-weighted sums (flow/linear_cone_model.h).
//
// Placement: greedy (add the vertex of largest |u|, from the curvature extremum on a closed
// surface of chi != 0; Springborn, Schroeder, Pinkall 2008) until the bound or the budget stops
// it, then Gauss-Seidel relocation (move a cone to the argmax |u| of the set without it where
// that lowers D, as CEPS does; where the budget stopped the greedy, to the best of several peaks
// of |u|), then the weakest cones dropped while the bound holds, until the distortion
//   D = sqrt(sum_i A_i (u_i - mean u)^2)
// (A_i the vertex areas of the surface scaled to area 1) is at most the bound and every cone
// angle at least the floor, or the cone budget is reached. Last, a cone that would open a corner
// of its faces past a half turn (its 3D corner times the cone angle over the vertex's 3D angle
// sum: near a cone the flat metric opens every corner about alike) is moved within two rings to
// the vertex of least D where it opens none past 0.9 pi and no other cone comes to open one past
// a half turn, where D stays within 5 % of the set's before these moves and the bound and the
// angle floor still hold where they held: such a corner cannot be one triangle's, and an atlas on
// the user's own faces would turn it over. Where the bound is not reached (a budget), the cones
// then take the curvatures of least D, u free at them: D is a quadratic form in k, minimized
// under the floors, the drawable corners and u at the cones within the held u's range
// (least_distortion_angles). Quarter angles are rounded after this, which can move a cone's
// angle, and with it the corners it opens, by up to a quarter turn.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/presets.h"
#include "ricci/linear/linear_solver.h"
#include "ricci/mesh/compact_mesh.h"

namespace ricci {

struct ConePlacementOptions {
  //! Stop adding cones when D is at most this (the sparse-cone literature's default).
  double distortion_bound = 0.2;
  //! The most cones; 0: kDefaultConeBudget.
  int max_cones = 0;
  //! The sharpest cone allowed (radians): a cone of angle theta = 2 pi - k needs theta at least
  //! this. pi / 4 keeps a cone's wedge laid out with corner angles the mesh's own triangles can
  //! have, and the exact flow's cone (which moves from the linear model's) still positive. At a
  //! vertex whose own angle sum (in 3D) is below twice this (a spike's tip), half that sum: no
  //! cone nearby widens a tip's own cone, since it is drawn from the tip's own faces.
  double min_cone_angle = kPi / 4;
  //! Gauss-Seidel relocation sweeps over the cones (0: the greedy's places, but for cones that
  //! would open a corner past a half turn).
  int relocation_sweeps = 4;
  //! Round every cone curvature to a multiple of pi / 2 (keeping their sum), for atlases whose
  //! charts meet by quarter turns; cones rounded to 0 are dropped.
  bool quarter_angles = false;
  //! Where the placement stops above the bound (at the budget, or with no vertex left) with at
  //! most kLeastDistortionCones cones: their curvatures of least D, u free at the cones (within
  //! the floors, drawable, and u at the cones within the range the held model's u spans), instead
  //! of those with u held at 0 there. At BFF's 8 cones D on the delivered faces fell on 54 of the
  //! 188 one-part files of the real set and CGAL's, by a median of 16 % (docs/atlas.md).
  bool least_distortion_angles = true;
  LinearSolverKind linear_solver = LinearSolverKind::Cholmod;
  //! From this many cones u over the vertices is solved for rather than summed from the cones'
  //! columns (LinearConeModel); 0: where that costs less, by the factor's size.
  int u_solved_from = 0;
};

//! The most cones whose curvatures of least D are solved for (least_distortion_angles): a dense
//! solve of up to twice their number a step. CGAL's camel for D 0.05 at 64 cones: placement 0.33
//! s, D 0.128 on its faces; at 128, 1.6 s, D 0.091; the cow 0.15 s and 1.1 s. Above it the held
//! model's curvatures stand, whose D at a budget is higher (the cow for 0.1: 0.0987 at 64 cones,
//! 0.170 at 65 before the limit was 128).
inline constexpr int kLeastDistortionCones = 128;
//! The default cone budget: above what a bound of 0.2 takes on real meshes (CGAL's cheese, genus
//! 133, takes 633; a 117k-face CAD head 353), so that it only stops a mesh that no number of
//! cones flattens within the bound (a very coarse one).
inline constexpr int kDefaultConeBudget = 1024;
//! The cone budget the options give: max_cones, or kDefaultConeBudget where that is 0.
inline int cone_budget(const ConePlacementOptions& o) {
  return o.max_cones > 0 ? o.max_cones : kDefaultConeBudget;
}
//! The max_cones for a budget a front end's user set: 0 (none given) where it is the default the
//! front end shows (a dialog's field, a command line's help), so that leaving it as shown keeps
//! the atlas's further attempts (cones of other counts for QC or a stall, an unfolding for QC),
//! which a budget of the user's stops.
inline int max_cones_asked(int budget) {
  return budget == kDefaultConeBudget ? 0 : budget;
}

struct ConePlacement {
  //! The cones, each with the angle 2 pi - k the linear model gives it (or its rounding).
  std::vector<Cone> cones;
  //! The linear model's u per vertex: 0 on the boundary, and at the cones unless their angles were
  //! rounded or are those of least D (then the mean is 0 on a closed surface).
  Eigen::VectorXd u;
  //! D of u on the surface scaled to area 1, and of the cone-free model where one exists (a
  //! surface with boundary, or a torus; NaN otherwise).
  double distortion = 0;
  double distortion_without_cones = 0;
  double max_deviation = 0;  //!< max |u - mean u|
  bool bound_reached = false;
  bool sharp_cone = false;  //!< a cone sharper than its floor remains (then !bound_reached)
  //! The cones' curvatures are those of least D (least_distortion_angles), not the held model's.
  bool least_distortion = false;
  //! When !bound_reached: no flat metric, a cone below its floor, or D above the bound, at the
  //! budget or with no vertex left; or quarter turns that leave D above the bound.
  std::string why_not;
  int factorizations = 0;
  //! Right-hand sides solved: the columns (in blocks), g's, and from many cones u's and the
  //! columns' sums (LinearConeModel).
  int back_solves = 0;
  int relocations = 0;  //!< cones moved by the sweeps and off corners past a half turn
  int dropped = 0;      //!< cones dropped at the end
  double seconds = 0;
};

//! Places cones on a mesh (one component) for a flat metric with D at most the bound.
//! \throws InvalidArgumentError for options out of range; SolverError when the Laplacian cannot be
//!   factored.
ConePlacement place_cones(const CompactMesh& mesh, const ConePlacementOptions& options = {});

//! D = sqrt(sum_i A_i (u_i - mean u)^2) with A_i a third of the input faces' areas at vertex i, on
//! the surface scaled to area 1 (u per vertex; the mean A-weighted).
double area_distortion(const CompactMesh& mesh, const Eigen::VectorXd& u);

}  // namespace ricci
