#include "ricci/flow/presets.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "flow/circle_condition.h"
#include "ricci/mesh/errors.h"

namespace ricci {

std::string to_string(TargetPreset p) {
  switch (p) {
    case TargetPreset::Automatic:
      return "auto";
    case TargetPreset::UnitDisk:
      return "disk";
    case TargetPreset::FreeBoundary:
      return "free-boundary";
    case TargetPreset::Zero:
      return "zero";
    case TargetPreset::Values:
      return "values";
    case TargetPreset::Atlas:
      return "atlas";
  }
  return "?";
}

TargetPreset target_preset_from_string(const std::string& name) {
  for (TargetPreset p :
       {TargetPreset::Automatic, TargetPreset::UnitDisk, TargetPreset::FreeBoundary,
        TargetPreset::Zero, TargetPreset::Values, TargetPreset::Atlas}) {
    if (to_string(p) == name) return p;
  }
  throw InvalidArgumentError("unknown target '" + name +
                             "'; choose auto, disk, free-boundary, zero, values or atlas");
}

Geometry preset_geometry(const Triangulation& mesh, TargetPreset preset) {
  switch (preset) {
    case TargetPreset::Automatic:
      return automatic_preset(mesh).second;
    case TargetPreset::Zero: {
      const int chi = mesh.euler_characteristic();
      if (chi < 0) return Geometry::Hyperbolic;
      return mesh.is_closed() && chi > 0 ? Geometry::Spherical : Geometry::Euclidean;
    }
    default:  // UnitDisk, FreeBoundary, Atlas; Values are decided by geometry_for_target
      return Geometry::Euclidean;
  }
}

std::pair<TargetPreset, Geometry> automatic_preset(const Triangulation& mesh) {
  const TargetPreset preset =
      !mesh.is_closed() && mesh.genus() == 0 ? TargetPreset::UnitDisk : TargetPreset::Zero;
  return {preset, preset_geometry(mesh, preset)};
}

Geometry geometry_for_target(const CompactMesh& mesh, const TargetCurvature& target) {
  if (target.num_fixed() > 0) return Geometry::Euclidean;
  double sum = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) sum += target.curvature[v];
  const double two_pi_chi = 2 * kPi * mesh.euler_characteristic();
  const double slack = 1e-9 * (std::max(1.0, std::abs(two_pi_chi)) + std::abs(sum));
  if (std::abs(sum - two_pi_chi) <= slack) return Geometry::Euclidean;
  return sum > two_pi_chi ? Geometry::Hyperbolic : Geometry::Spherical;
}

TargetCurvature cone_target(const CompactMesh& mesh, const std::vector<Cone>& cones) {
  TargetCurvature t = TargetCurvature::zero(mesh);
  std::set<int> seen;
  for (const Cone& c : cones) {
    if (c.vertex < 0 || c.vertex >= mesh.num_vertices()) {
      throw InvalidTargetError("cone at vertex " + std::to_string(c.vertex) +
                               ": the mesh has vertices 0.." +
                               std::to_string(mesh.num_vertices() - 1));
    }
    if (!seen.insert(c.vertex).second) {
      throw InvalidTargetError("cone at vertex " + std::to_string(c.vertex) +
                               " is given twice; give each vertex once");
    }
    if (!(c.angle > 0) || !std::isfinite(c.angle)) {
      throw InvalidTargetError("cone at vertex " + std::to_string(c.vertex) +
                               ": the angle must be positive and finite");
    }
    t.curvature[c.vertex] = (mesh.is_boundary_vertex(c.vertex) ? kPi : 2 * kPi) - c.angle;
  }
  return t;
}

int outer_boundary_loop(const Triangulation& mesh, const std::vector<double>& lengths) {
  const auto loops = detail::loop_edges(mesh);
  int best = -1;
  double best_length = -1;
  for (size_t c = 0; c < loops.size(); ++c) {
    double length = 0;
    for (int e : loops[c]) length += lengths[e];
    if (length > best_length) best = static_cast<int>(c), best_length = length;
  }
  return best;
}

TargetCurvature circle_boundary_target(const Triangulation& mesh,
                                       const std::vector<double>& lengths, int outer_loop) {
  TargetCurvature t;
  t.curvature = Eigen::VectorXd::Zero(mesh.num_vertices());
  t.fixed.assign(mesh.num_vertices(), 0);
  detail::CircleCondition(mesh, outer_loop).set_target(lengths, t);
  return t;
}

}  // namespace ricci
