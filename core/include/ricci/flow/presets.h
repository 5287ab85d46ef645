// Target curvature presets: which metric a user asks for, by name, and the boundary curvature
// that puts boundary loops on circles (unit disk, circle domain).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "ricci/flow/target.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/mesh/geometry.h"

namespace ricci {

enum class TargetPreset {
  Automatic,     //!< by topology (automatic_preset())
  UnitDisk,      //!< genus 0 with boundary: boundaries on circles, the outer one the unit circle
  FreeBoundary,  //!< u = 0 on the boundary, Kbar = 0 inside
  Zero,          //!< Kbar = 0 everywhere (closed surfaces; geodesic boundaries in H2)
  Values,        //!< Kbar per vertex given by the caller (cones, files, vertex quality)
  Atlas,         //!< a texture atlas: cones placed for bounded area distortion (cone_placement.h),
                 //!< u held at them and on the boundary, flat elsewhere (E2)
};

//! "auto", "disk", "free-boundary", "zero", "values", "atlas".
std::string to_string(TargetPreset p);
//! Inverse of to_string. \throws InvalidArgumentError naming the choices.
TargetPreset target_preset_from_string(const std::string& name);

//! The geometry of a preset on the mesh's topology, the one rule every choice goes through:
//! UnitDisk, FreeBoundary and Atlas are flat (E2). Zero: on a closed surface the sign of the Euler
//! characteristic (Gauss-Bonnet, 2 pi chi = kappa A): S2 for genus 0, E2 for genus 1, H2 for
//! genus >= 2; with boundary (geodesic boundary) H2 when chi < 0, else E2. Automatic: that of
//! automatic_preset. Values: Gauss-Bonnet decides (geometry_for_target).
Geometry preset_geometry(const Triangulation& mesh, TargetPreset preset);

//! The uniformization theorem's choice: genus 0 with boundary -> UnitDisk (the unit disk, or a
//! circle domain for several boundary loops); every other surface -> Zero (round sphere, flat
//! torus, hyperbolic metric with geodesic boundary); each in its preset_geometry.
std::pair<TargetPreset, Geometry> automatic_preset(const Triangulation& mesh);

//! The geometry Gauss-Bonnet admits for explicit targets: E2 when some u is fixed or
//! sum Kbar = 2 pi chi, H2 when sum Kbar > 2 pi chi, S2 when it is smaller.
Geometry geometry_for_target(const CompactMesh& mesh, const TargetCurvature& target);

//! A cone (interior vertex) or corner (boundary vertex) of angle `angle` radians.
struct Cone {
  int vertex = 0;
  double angle = 0;
};

//! Kbar = 2 pi - angle at interior cones, pi - angle at boundary corners, 0 at every other
//! vertex (flat inside, straight boundary): cone metrics, rectangles and polygons.
//! \throws InvalidTargetError for a vertex out of range, a repeated vertex or an angle <= 0.
TargetCurvature cone_target(const CompactMesh& mesh, const std::vector<Cone>& cones);

//! The boundary loop taken as the outer circle: the longest in the metric `lengths`.
int outer_boundary_loop(const Triangulation& mesh, const std::vector<double>& lengths);

//! Kbar for a flat metric whose boundary loops are circles: interior vertices 0, a boundary
//! vertex of loop c the turning of a circle through its edges (half the central angles of its
//! two boundary edges, chords of a circle of radius R_c with central angles summing to 2 pi),
//! positive on the outer loop, negative on the others. With the current lengths of a flat
//! metric, a fixed point of flow -> circle_boundary_target is a circle domain.
TargetCurvature circle_boundary_target(const Triangulation& mesh,
                                       const std::vector<double>& lengths, int outer_loop);

}  // namespace ricci
