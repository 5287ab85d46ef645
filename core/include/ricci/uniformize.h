// Uniformization: a target preset, the flow, and the layout of the result in its model space,
// measured. The one pipeline behind `ricci-flow` and the MeshLab filter.
//
//   disk (E2)              least-squares planar layout (layout.h); with the disk preset on the
//                          unit circle, optionally Moebius-normalized (center and axis vertex)
//   circle domain (E2)     genus 0 with several boundary loops, disk preset: developed across a
//                          cut (deck transformations ~ identity), outer loop the unit circle
//   cut open (E2, H2)      torus, higher genus, other targets: per-corner (wedge) positions in
//                          the plane or the Poincare disk, deck transformations, closure error
//   sphere (S2)            genus 0: vertices on the unit sphere, centre of mass at the origin
#pragma once

#include <array>
#include <complex>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/compact_mesh.h"
#include "ricci/layout.h"
#include "ricci/layout_quality.h"
#include "ricci/model_layout.h"
#include "ricci/presets.h"
#include "ricci/ricci_flow.h"

namespace ricci {

enum class LayoutKind {
  None,          //!< no layout (S2 with a cut)
  Plane,         //!< one position per vertex in the plane (disks, circle domains)
  PlaneCut,      //!< E2 cut open: wedge positions
  PoincareDisk,  //!< H2 cut open: wedge positions in the unit disk
  Sphere,        //!< one position per vertex on the unit sphere
};
//! "none", "plane", "plane-cut", "poincare-disk", "sphere".
std::string to_string(LayoutKind k);

struct UniformizationOptions {
  TargetPreset preset = TargetPreset::Automatic;
  //! The geometry; empty: the preset's (automatic_preset), or for Values the one Gauss-Bonnet
  //! admits (geometry_for_target).
  std::optional<Geometry> geometry;
  //! Values: Kbar per vertex, NaN where u stays fixed.
  Eigen::VectorXd values;
  SchemeOptions scheme;
  FlowOptions flow;
  //! Disk preset: the vertex mapped to the centre of the unit disk, and the one mapped onto the
  //! positive real axis (-1: none).
  int center_vertex = -1, axis_vertex = -1;
  //! Disk preset: the boundary curvature is re-fitted to the boundary's current lengths until it
  //! changes by less than this (radians).
  double boundary_tolerance = 1e-9;
  int max_boundary_iterations = 200;
};

struct Uniformization {
  TargetPreset preset = TargetPreset::Automatic;  //!< the one used (never Automatic)
  Geometry geometry = Geometry::Euclidean;
  ConformalStructure structure;  //!< the initial structure
  FlowResult result;
  int boundary_iterations = 0;  //!< disk preset: flows run while fitting the boundary
  int newton_iterations = 0;    //!< over all those flows
  double boundary_change = 0;   //!< disk preset: last change of the boundary curvature
  double circle_error = 0;      //!< disk preset: max | |z - c| - r | / r over boundary loops

  LayoutKind layout = LayoutKind::None;
  //! Plane and Sphere: position per vertex (Plane: z = 0).
  std::vector<Eigen::Vector3d> position;
  //! Every layout: positions per face and corner of the input mesh.
  std::vector<std::array<Eigen::Vector3d, 3>> corners;
  std::optional<ModelLayout> model;      //!< the developed layout (all but E2 disks)
  double max_relative_length_error = 0;  //!< E2 disks: of the least-squares layout
  double relation_error = 0;             //!< surface_group_relation_error
  //! Flat torus (E2, closed genus 1): two translations spanning the period lattice, from the deck
  //! transformations; |Im(conj(w0) w1)| is the torus's area.
  std::vector<std::complex<double>> periods;
  LayoutQuality quality;
};

//! The preset (never Automatic) and geometry a request resolves to, checked.
//! \throws InvalidTargetError, InvalidArgumentError naming what cannot be done and why.
std::pair<TargetPreset, Geometry> resolve_request(const CompactMesh& mesh,
                                                  const UniformizationOptions& options);

//! The kind of layout uniformize() gives for a resolved request, when the flow converges.
LayoutKind planned_layout(const Triangulation& mesh, TargetPreset preset, Geometry geometry);

//! Runs the preset's flow and lays out the result.
//! \throws InvalidTargetError, InvalidArgumentError for requests that admit no solution (named),
//!   ConvergenceError when the flow does not converge.
Uniformization uniformize(const CompactMesh& mesh, const UniformizationOptions& options);

//! Texture coordinates in [0, 1]^2 of a layout: per vertex for Plane (scaled with the aspect ratio
//! kept), per face corner for PlaneCut (the same) and PoincareDisk ((z + 1) / 2); none for the
//! sphere.
struct TextureCoordinates {
  std::vector<Eigen::Vector2d> vertex;
  std::vector<std::array<Eigen::Vector2d, 3>> wedge;
};
TextureCoordinates texture_coordinates(const Uniformization& u);

//! The points scaled and moved so that the circle fitted to the `boundary` points is the unit
//! circle; then, with center >= 0, the Moebius map of the unit disk taking point `center` to 0,
//! and with axis >= 0 the rotation taking point `axis` onto the positive real axis.
//! \throws InvalidArgumentError when center lies on the circle or axis at the centre.
std::vector<Eigen::Vector3d> normalize_to_unit_disk(std::vector<Eigen::Vector3d> points,
                                                    const std::vector<int>& boundary, int center,
                                                    int axis);

}  // namespace ricci
