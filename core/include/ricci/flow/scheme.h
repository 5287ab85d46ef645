// The six schemes as data: per-vertex eps in {+1, 0, -1}, per-edge eta, and the
// initial conformal factor u0 (paper, Section 3 table; Appendix Step 1).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/compact_mesh.h"
#include "ricci/mesh/geometry.h"

namespace ricci {

enum class Scheme {
  Tangential,         //!< eps = +1, eta = 1
  Thurston,           //!< eps = +1, eta = cos(Phi)
  InversiveDistance,  //!< eps = +1, eta from the input lengths
  Yamabe,             //!< eps = 0, eta from the input lengths
  VirtualRadius,      //!< eps = -1, eta from the input lengths
  Mixed,              //!< eps per vertex (caller), eta from the input lengths
};

//! "tangential", "thurston", "inversive-distance", "yamabe", "virtual-radius", "mixed".
std::string to_string(Scheme s);
//! Inverse of to_string. \throws InvalidArgumentError for an unknown name.
Scheme scheme_from_string(const std::string& name);

//! True for the schemes whose initial metric reproduces the input lengths.
bool reproduces_input_lengths(Scheme s);

struct SchemeOptions {
  Scheme scheme = Scheme::Yamabe;
  //! Thurston's intersection angle Phi in radians, in [0, pi/2].
  double intersection_angle = kPi / 3;
  //! Mixed scheme: eps per vertex, each +1, 0 or -1.
  std::vector<int> eps;
  //! Virtual radius (eps = -1) and eps = 0 vertices of the mixed scheme: initial radius as a
  //! fraction of the median length of the vertex's edges. Small is robust: with edge flips, 0.05
  //! converged on every Euclidean and hyperbolic scan tried, 0.3 only on smooth meshes (DESIGN.md
  //! saw 1 stall).
  double virtual_radius_fraction = 0.05;
};

//! A circle packing metric up to the conformal factor: (eps, eta) and the starting u.
struct ConformalStructure {
  Geometry geometry = Geometry::Euclidean;
  std::vector<int> eps;     //!< per vertex
  std::vector<double> eta;  //!< per edge
  Eigen::VectorXd u0;       //!< initial conformal factor per vertex
  double length_scale = 1;  //!< input lengths were multiplied by this (H2, S2)
};

//! Every vertex has eps = 0: the Yamabe flow's length law, whose edge flips (Ptolemy's relation)
//! keep the discrete conformal class.
bool is_yamabe(const ConformalStructure& structure);

//! Checks the options that need no mesh: Thurston's angle in [0, pi/2], a positive virtual
//! radius fraction, eps values in {+1, 0, -1}. \throws InvalidArgumentError naming the value.
void check_scheme_options(const SchemeOptions& options);

//! Builds eps, eta and u0 for the scheme from the mesh's input lengths times length_scale.
//! Yamabe: u0 = 0 in every geometry. Inversive distance (and eps = +1 vertices of the mixed
//! scheme): r = min incident length / 3; virtual radius (and eps = 0, -1 vertices of the mixed
//! scheme): r = virtual_radius_fraction x median incident length; tangential and Thurston: radii
//! fitted to the input lengths (their eta is prescribed, so the input metric is not reproduced).
//! Where eta is not prescribed it then solves the length law for the scaled input lengths.
//! \pre length_scale > 0, and in S2 every scaled triangle has perimeter below 2 pi.
//! \throws InvalidArgumentError for a bad angle or eps array.
ConformalStructure initialize_scheme(const CompactMesh& mesh, Geometry geometry,
                                     const SchemeOptions& options, double length_scale = 1);

}  // namespace ricci
