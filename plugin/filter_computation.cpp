#include "filter_computation.h"

#include <cmath>
#include <optional>

#include "ricci/mesh/errors.h"

namespace ricci::plugin {

namespace {

std::optional<Geometry> chosen_geometry(GeometryChoice choice) {
  switch (choice) {
    case GeometryChoice::Auto:
      return std::nullopt;
    case GeometryChoice::Euclidean:
      return Geometry::Euclidean;
    case GeometryChoice::Hyperbolic:
      return Geometry::Hyperbolic;
    case GeometryChoice::Spherical:
      return Geometry::Spherical;
  }
  return std::nullopt;
}

void choose_target(const MeshInput& in, TargetChoice choice, UniformizationOptions& o) {
  switch (choice) {
    case TargetChoice::Auto:
      o.preset = TargetPreset::Automatic;
      return;
    case TargetChoice::FreeBoundary:
      o.preset = TargetPreset::FreeBoundary;
      return;
    case TargetChoice::Zero:
      o.preset = TargetPreset::Zero;
      return;
    case TargetChoice::UnitDisk:
      o.preset = TargetPreset::UnitDisk;
      return;
    case TargetChoice::Atlas:
      o.preset = TargetPreset::Atlas;
      return;
    case TargetChoice::VertexQuality:
      if (in.quality.empty()) {
        throw InvalidTargetError(
            "target 'Per vertex from vertex quality': the mesh has no vertex "
            "quality; compute one first (e.g. Filters > Quality Measure "
            "and Computations > Per Vertex Quality Function)");
      }
      o.preset = TargetPreset::Values;
      o.values = Eigen::Map<const Eigen::VectorXd>(in.quality.data(),
                                                   static_cast<long>(in.quality.size()));
      return;
  }
}

// A vertex index of the MeshLab mesh (its storage slot) as an index of the compact mesh.
int compact_vertex(const MeshInput& in, int slot, const char* what) {
  if (slot < 0) return -1;
  if (slot >= static_cast<int>(in.compact_index.size()) || in.compact_index[slot] < 0) {
    throw InvalidArgumentError(std::string(what) + " vertex " + std::to_string(slot) +
                               " is not a vertex of the mesh (indices 0.." +
                               std::to_string(static_cast<int>(in.compact_index.size()) - 1) +
                               ", deleted ones excluded); give another index, or -1 for none");
  }
  return in.compact_index[slot];
}

std::vector<int> mixed_eps(const MeshInput& in, MixedEpsSource source) {
  std::vector<int> eps(in.selected.size(), 0);
  if (source == MixedEpsSource::Selection) {
    for (size_t v = 0; v < eps.size(); ++v) eps[v] = in.selected[v] ? 1 : 0;
    return eps;
  }
  if (in.quality.empty()) {
    throw InvalidArgumentError(
        "mixed scheme: eps from the sign of vertex quality, but the mesh "
        "has no vertex quality; select the circle packing vertices "
        "instead, or compute a quality first");
  }
  for (size_t v = 0; v < eps.size(); ++v) {
    eps[v] = in.quality[v] > 0 ? 1 : (in.quality[v] < 0 ? -1 : 0);
  }
  return eps;
}

}  // namespace

FilterComputation compute(const MeshInput& input, const FilterSettings& settings,
                          const std::function<bool(const FlowProgress&)>& progress) {
  UniformizationOptions o;
  o.geometry = chosen_geometry(settings.geometry);
  choose_target(input, settings.target, o);
  o.center_vertex = compact_vertex(input, settings.center_vertex, "the center");
  o.axis_vertex = compact_vertex(input, settings.axis_vertex, "the axis");
  o.scheme.scheme = settings.scheme;
  o.scheme.intersection_angle = settings.thurston_angle_degrees * kPi / 180;
  if (settings.scheme == Scheme::Mixed) o.scheme.eps = mixed_eps(input, settings.mixed_eps);
  o.flow.tolerance = settings.tolerance;
  o.flow.max_iterations = settings.max_iterations;
  o.flow.linear_solver = settings.linear_solver;
  o.flow.max_step_halvings = settings.max_step_halvings;
  o.flow.edge_flips = !settings.edge_flips   ? EdgeFlips::Never
                      : settings.always_flip ? EdgeFlips::Always
                                             : EdgeFlips::WhenNeeded;
  o.keep_input_triangulation = settings.keep_input_triangulation;
  o.cone_placement.distortion_bound = settings.atlas_distortion;
  o.cone_placement.max_cones = max_cones_asked(settings.atlas_max_cones);
  o.cone_placement.quarter_angles = settings.atlas_quarter_angles;
  o.packing.texture_size = settings.atlas_texture_size;
  o.packing.padding = settings.atlas_padding;
  o.flow.progress = progress;
  FilterComputation c;
  c.run = uniformize_mesh(input.repaired, o);
  c.run.require_valid();
  return c;
}

WrittenComponents written_components(const FilterSettings& settings, const FilterComputation& c) {
  WrittenComponents w;
  w.quality_and_color = settings.write_quality;
  w.vertex_texcoord = settings.write_texture_coordinates && !c.texture().vertex.empty();
  w.wedge_texcoord = settings.write_texture_coordinates && !c.texture().wedge.empty();
  w.layout_layer = settings.add_layout_layer && c.has_vertex_layout();
  return w;
}

}  // namespace ricci::plugin
