#include "ricci/flow/ricci_flow.h"

// The flow's one-shot calls: the initial structure, the stereographic start, one solve.
#include <algorithm>
#include <cmath>
#include <optional>

#include "flow/spherical_start.h"
#include "ricci/mesh/errors.h"

namespace ricci {

double initial_length_scale(const CompactMesh& mesh, Geometry geometry,
                            const TargetCurvature& target) {
  if (geometry == Geometry::Euclidean) return 1;
  double area = gauss_bonnet_area(mesh, geometry, target);
  if (!(area > 0)) area = 1;
  double scale = std::sqrt(area / mesh.input_area());
  if (geometry == Geometry::Spherical) {
    double max_perimeter = 0;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      double p = 0;
      for (int c = 0; c < 3; ++c) p += mesh.input_lengths()[mesh.face_edge(f, c)];
      max_perimeter = std::max(max_perimeter, p);
    }
    scale = std::min(scale, kPi / max_perimeter);
  }
  return scale;
}

ConformalStructure prepare_flow(const CompactMesh& mesh, Geometry geometry,
                                const SchemeOptions& scheme, const TargetCurvature& target) {
  check_target(mesh, geometry, target);
  return initialize_scheme(mesh, geometry, scheme, initial_length_scale(mesh, geometry, target));
}

FlowResult run_ricci_flow(const CompactMesh& mesh, const ConformalStructure& structure,
                          const TargetCurvature& target, const FlowOptions& options) {
  check_target(mesh, structure.geometry, target);
  RicciFlowSolver solver(mesh, structure, options);
  const std::optional<Eigen::VectorXd> start = flow_start(mesh, structure, target, options);
  return solver.solve(target, start ? &*start : nullptr);
}

FlowResult compute_ricci_flow(const CompactMesh& mesh, Geometry geometry,
                              const SchemeOptions& scheme, const TargetCurvature& target,
                              const FlowOptions& options) {
  const ConformalStructure structure = prepare_flow(mesh, geometry, scheme, target);
  FlowResult result = run_ricci_flow(mesh, structure, target, options);
  if (!result.converged) {
    throw ConvergenceError(flow_failure_message(geometry, scheme.scheme, result), result.iterations,
                           result.residual);
  }
  return result;
}

std::string flow_failure_message(Geometry geometry, Scheme scheme, const FlowResult& result,
                                 const std::string& subject) {
  return "ricci flow (" + to_string(geometry) + ", " + to_string(scheme) + ")" +
         (subject.empty() ? "" : " on " + subject) + ": " + result.failure;
}

}  // namespace ricci
