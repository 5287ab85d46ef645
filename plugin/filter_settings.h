// The filter's parameters as plain data, independent of MeshLab's plugin API: the table every
// adapter turns into its own dialog, and the translation of chosen values into core options.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "ricci/flow/ricci_flow.h"
#include "ricci/flow/scheme.h"
#include "ricci/linear/linear_solver.h"
#include "ricci/mesh/geometry.h"
#include "ricci/pipeline/uniformize.h"
#include "ricci/repair/repair.h"

namespace ricci::plugin {

enum class GeometryChoice { Auto, Euclidean, Hyperbolic, Spherical };
enum class MixedEpsSource { Selection, QualitySign };
//! In dialog order; new choices are appended so that saved scripts keep their meaning.
enum class TargetChoice { Auto, FreeBoundary, Zero, VertexQuality, UnitDisk, Atlas };

//! Everything the filter needs to know, in core terms. The defaults are the core's (its option
//! structs), and the dialog's defaults are these.
struct FilterSettings {
  GeometryChoice geometry = GeometryChoice::Auto;
  Scheme scheme = SchemeOptions{}.scheme;
  double thurston_angle_degrees = SchemeOptions{}.intersection_angle * 180 / kPi;
  MixedEpsSource mixed_eps = MixedEpsSource::Selection;
  TargetChoice target = TargetChoice::Auto;
  int center_vertex = UniformizationOptions{}.center_vertex;  //!< mesh vertex slot, -1: none
  int axis_vertex = UniformizationOptions{}.axis_vertex;      //!< mesh vertex slot, -1: none
  double tolerance = FlowOptions{}.tolerance;
  int max_iterations = FlowOptions{}.max_iterations;
  LinearSolverKind linear_solver = FlowOptions{}.linear_solver;
  int max_step_halvings = FlowOptions{}.max_step_halvings;
  bool edge_flips = FlowOptions{}.edge_flips != EdgeFlips::Never;
  bool always_flip = FlowOptions{}.edge_flips == EdgeFlips::Always;  //!< with edge_flips
  bool write_texture_coordinates = true;
  bool write_quality = true;
  bool add_layout_layer = false;
  RepairOptions repair;  //!< refuse a mesh that needs repairs (strict); keep its cuts
  //! lay out the mesh's own faces even where flips turn them over (no common subdivision)
  bool keep_input_triangulation = UniformizationOptions{}.keep_input_triangulation;
  //! The atlas target's cone placement and packing (cone_placement.h, packing.h).
  double atlas_distortion = ConePlacementOptions{}.distortion_bound;
  int atlas_max_cones = kDefaultConeBudget;
  bool atlas_quarter_angles = ConePlacementOptions{}.quarter_angles;
  int atlas_texture_size = PackingOptions{}.texture_size;
  int atlas_padding = PackingOptions{}.padding;
};

//! One dialog parameter.
struct ParameterSpec {
  enum class Kind { Enum, Float, Int, Bool };
  std::string name;  //!< the name in .mlx scripts
  Kind kind;
  double default_value;
  std::vector<std::string> enum_labels;  //!< Enum only
  std::string description;               //!< the dialog's label
  std::string tooltip;
};

//! The parameters in dialog order.
const std::vector<ParameterSpec>& parameter_specs();

//! Values by parameter name: enum index, number, or 0/1.
using ParameterValues = std::map<std::string, double>;

//! Translates values (missing ones take their defaults).
//! \throws InvalidArgumentError for an out-of-range enum index, tolerance or count.
FilterSettings settings_from_values(const ParameterValues& values);

//! The filter's menu name and its help text.
std::string filter_name();
std::string filter_info();

//! The filter's name in pymeshlab (MeshLab 2021.05 and later): a function of pymeshlab.MeshSet.
std::string python_filter_name();
//! A parameter's name as pymeshlab shows it (keyword arguments): the .mlx name in snake case,
//! "thurstonAngle" -> "thurston_angle", "writeUV" -> "write_uv".
std::string python_parameter_name(const std::string& script_name);

}  // namespace ricci::plugin
