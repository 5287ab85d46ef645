#include "filter_computation.h"

#include <cmath>
#include <sstream>

#include "ricci/errors.h"

namespace ricci::plugin {

namespace {

constexpr double kPi = 3.14159265358979323846;

Geometry choose_geometry(GeometryChoice choice, const CompactMesh& mesh) {
  switch (choice) {
    case GeometryChoice::Auto:
      return automatic_geometry(mesh);
    case GeometryChoice::Euclidean:
      return Geometry::Euclidean;
    case GeometryChoice::Hyperbolic:
      return Geometry::Hyperbolic;
    case GeometryChoice::Spherical:
      return Geometry::Spherical;
  }
  return Geometry::Euclidean;
}

TargetCurvature choose_target(const MeshInput& in, TargetChoice choice) {
  const CompactMesh& mesh = in.mesh;
  switch (choice) {
    case TargetChoice::Auto:
      return TargetCurvature::automatic(mesh);
    case TargetChoice::FreeBoundary:
      if (mesh.is_closed()) {
        throw InvalidTargetError("target 'Free boundary' needs a boundary, but the mesh is a " +
                                 mesh.topology_name() + "; choose 'Zero curvature everywhere'");
      }
      return TargetCurvature::free_boundary(mesh);
    case TargetChoice::Zero:
      return TargetCurvature::zero(mesh);
    case TargetChoice::VertexQuality:
      if (in.quality.empty()) {
        throw InvalidTargetError(
            "target 'Per vertex from vertex quality': the mesh has no vertex "
            "quality; compute one first (e.g. Filters > Quality Measure "
            "and Computations > Per Vertex Quality Function)");
      }
      return TargetCurvature::from_values(
          mesh, Eigen::Map<const Eigen::VectorXd>(in.quality.data(),
                                                  static_cast<long>(in.quality.size())));
  }
  return TargetCurvature::automatic(mesh);
}

std::vector<int> mixed_eps(const MeshInput& in, MixedEpsSource source) {
  std::vector<int> eps(in.mesh.num_vertices(), 0);
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
  const CompactMesh& mesh = input.mesh;
  FilterComputation c;
  c.geometry = choose_geometry(settings.geometry, mesh);
  SchemeOptions scheme;
  scheme.scheme = settings.scheme;
  scheme.intersection_angle = settings.thurston_angle_degrees * kPi / 180;
  if (settings.scheme == Scheme::Mixed) scheme.eps = mixed_eps(input, settings.mixed_eps);
  const TargetCurvature target = choose_target(input, settings.target);
  FlowOptions options;
  options.tolerance = settings.tolerance;
  options.max_iterations = settings.max_iterations;
  options.linear_solver = settings.linear_solver;
  options.max_step_halvings = settings.max_step_halvings;
  options.edge_flips = settings.edge_flips;
  options.progress = progress;
  c.result = compute_ricci_flow(mesh, c.geometry, scheme, target, options);
  if (c.geometry == Geometry::Euclidean && mesh.is_disk()) {
    c.layout = layout_disk(result_triangulation(mesh, c.result), c.result.edge_lengths,
                           settings.linear_solver);
    c.flipped_input_faces = count_flipped_faces(mesh, c.layout->position);
    c.texture = normalized_texture_coordinates(c.layout->position);
  }
  return c;
}

std::vector<std::string> summary(const MeshInput& input, const FilterSettings& settings,
                                 const FilterComputation& c) {
  const CompactMesh& mesh = input.mesh;
  std::vector<std::string> lines;
  std::ostringstream s;
  s << "Ricci flow: " << mesh.topology_name() << ", " << mesh.num_vertices() << " vertices, "
    << mesh.num_faces() << " faces; " << to_string(c.geometry) << " geometry, "
    << to_string(settings.scheme) << " scheme";
  lines.push_back(s.str());
  s.str("");
  s.precision(3);
  s << "Converged in " << c.result.iterations << " Newton iterations with " << c.result.num_flips
    << " edge flips: max |K - Kbar| = " << c.result.residual << " (" << c.result.times.total
    << " s)";
  lines.push_back(s.str());
  if (c.layout) {
    s.str("");
    s << "Planar layout: " << c.flipped_input_faces << " of the mesh's faces flipped, max relative "
      << "edge length error " << c.layout->max_relative_length_error;
    lines.push_back(s.str());
  } else {
    lines.push_back("No layout written: only Euclidean disks are laid out so far (this is a " +
                    mesh.topology_name() + " in " + to_string(c.geometry) + " geometry)");
  }
  return lines;
}

}  // namespace ricci::plugin
