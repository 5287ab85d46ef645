// ricci-flow: the unified discrete surface Ricci flow on one mesh, from the command line.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/Core>

#include "options.h"
#include "picture.h"
#include "report.h"
#include "result_ply.h"
#include "ricci/errors.h"
#include "ricci/mesh_io.h"
#include "ricci/uniformize.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

// --target: a preset name, cones:FILE, or a file of Kbar values.
void set_target(const std::string& spec, const ricci::CompactMesh& mesh,
                ricci::UniformizationOptions& u) {
  using namespace ricci;
  for (const char* name : {"auto", "disk", "free-boundary", "zero"}) {
    if (spec == name) {
      u.preset = target_preset_from_string(spec);
      return;
    }
  }
  TargetCurvature target;
  if (spec.rfind("cones:", 0) == 0) {
    std::vector<Cone> cones;
    for (const auto& [vertex, degrees] : cli::read_cones(spec.substr(6))) {
      cones.push_back({vertex, degrees * kPi / 180});
    }
    target = cone_target(mesh, cones);
  } else {
    const std::vector<double> values = cli::read_numbers(spec);
    target = TargetCurvature::from_values(
        mesh, Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<long>(values.size())));
  }
  u.preset = TargetPreset::Values;
  u.values = target.curvature;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (target.is_fixed(v)) u.values[v] = std::numeric_limits<double>::quiet_NaN();
  }
}

std::vector<int> read_eps(const std::string& path, int num_vertices) {
  const std::vector<double> values = ricci::cli::read_numbers(path);
  if (static_cast<int>(values.size()) != num_vertices) {
    throw ricci::InvalidArgumentError("--eps " + path + ": " + std::to_string(values.size()) +
                                      " values for " + std::to_string(num_vertices) +
                                      " vertices; give one of +1, 0, -1 per vertex");
  }
  std::vector<int> eps(values.size());
  for (size_t v = 0; v < values.size(); ++v) {
    if (values[v] != 1 && values[v] != 0 && values[v] != -1) {
      throw ricci::InvalidArgumentError("--eps " + path + ": vertex " + std::to_string(v) +
                                        " has " + std::to_string(values[v]) +
                                        "; each value must be +1, 0 or -1");
    }
    eps[v] = static_cast<int>(values[v]);
  }
  return eps;
}

int run(const ricci::cli::Options& o) {
  using namespace ricci;
  const bool show_progress = !o.quiet && isatty(fileno(stderr));
  const auto read_start = std::chrono::steady_clock::now();
  const CompactMesh mesh = read_mesh(o.input);
  const double read_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();

  UniformizationOptions request;
  if (o.geometry != "auto") request.geometry = geometry_from_string(o.geometry);
  set_target(o.target, mesh, request);
  request.center_vertex = o.center_vertex;
  request.axis_vertex = o.axis_vertex;
  SchemeOptions& scheme = request.scheme;
  scheme.scheme = scheme_from_string(o.scheme);
  scheme.intersection_angle = o.angle_degrees * kPi / 180;
  if (scheme.scheme == Scheme::Mixed) {
    if (o.eps_file.empty()) {
      throw InvalidArgumentError("the mixed scheme needs --eps FILE (+1, 0 or -1 per vertex)");
    }
    scheme.eps = read_eps(o.eps_file, mesh.num_vertices());
  } else if (!o.eps_file.empty()) {
    throw InvalidArgumentError("--eps is used only by --scheme mixed");
  }
  FlowOptions& flow = request.flow;
  flow.tolerance = o.tolerance;
  flow.max_iterations = o.max_iterations;
  flow.linear_solver = linear_solver_from_string(o.solver);
  flow.edge_flips = o.edge_flips;
  if (show_progress) {
    flow.progress = [](const FlowProgress& p) {
      std::fprintf(stderr, "\riteration %3d   max |K - Kbar| = %.3e ", p.iteration, p.residual);
      return true;
    };
  }
  const auto [preset, resolved_geometry] = resolve_request(mesh, request);
  const LayoutKind planned = planned_layout(mesh, preset, resolved_geometry);
  if (!o.picture.empty() && planned != LayoutKind::Plane) {
    throw InvalidArgumentError(
        "--picture needs a layout in the plane (a disk, or a circle domain with --target disk); "
        "this run is " +
        to_string(resolved_geometry) + " on a " + mesh.topology_name() + ", laid out as " +
        to_string(planned));
  }
  const Uniformization u = uniformize(mesh, request);
  const FlowResult& result = u.result;
  const Geometry geometry = u.geometry;
  if (show_progress) std::fprintf(stderr, "\n");

  cli::RunSummary summary;
  summary.input = o.input;
  summary.scheme = scheme.scheme;
  summary.target = o.target;
  summary.tolerance = o.tolerance;
  summary.initial_length_error = cli::initial_length_error(mesh, u.structure);
  summary.read_seconds = read_seconds;

  cli::ResultLayout written;
  written.position = u.position;
  TextureCoordinates uv = texture_coordinates(u);
  written.texture = std::move(uv.vertex);
  written.wedge_texture = std::move(uv.wedge);
  if (!o.report.empty()) cli::write_report(o.report, mesh, summary, u);
  if (!result.converged) {
    throw ConvergenceError("ricci flow (" + to_string(geometry) + ", " + to_string(scheme.scheme) +
                               ") on " + o.input + ": " + result.failure,
                           result.iterations, result.residual);
  }
  cli::write_result_ply(o.output, mesh, result, written, o.ascii);
  if (!o.picture.empty()) {
    cli::write_layout_png(o.picture, mesh, written.texture, result.u);
  }
  if (!o.quiet) {
    std::printf("%s: %s, %d vertices, %d faces; %s geometry, %s scheme\n", o.input.c_str(),
                mesh.topology_name().c_str(), mesh.num_vertices(), mesh.num_faces(),
                to_string(geometry).c_str(), to_string(scheme.scheme).c_str());
    std::printf(
        "converged in %d Newton iterations, %d edge flips: max |K - Kbar| = %.2e (%.3f s)\n",
        result.iterations, result.num_flips, result.residual, result.times.total);
    if (u.preset == TargetPreset::UnitDisk) {
      std::printf("boundary on circles after %d flows (%d Newton iterations): circle error %.2e\n",
                  u.boundary_iterations, u.newton_iterations, u.circle_error);
    }
    if (u.layout != LayoutKind::None) {
      const LayoutQuality& q = u.quality;
      std::printf(
          "layout (%s): %d of the input's faces flipped; quasi-conformal ratio median "
          "%.4f, 95%% %.4f, max %.4g; area ratio 5%%..95%% %.3g..%.3g\n",
          to_string(u.layout).c_str(), q.flipped_faces, q.quasi_conformal_median,
          q.quasi_conformal_p95, q.quasi_conformal_max, q.area_ratio_p5, q.area_ratio_p95);
    }
    if (u.model && !u.model->cut.paths.empty()) {
      std::printf(
          "cut into a disk along %zu paths (%d generators): closure error %.2e, "
          "relation error %.2e\n",
          u.model->cut.paths.size(), u.model->cut.num_generators, u.model->closure_error,
          u.relation_error);
    }
    if (!u.periods.empty()) {
      std::printf("flat torus: periods (%.6g, %.6g) and (%.6g, %.6g)\n", u.periods[0].real(),
                  u.periods[0].imag(), u.periods[1].real(), u.periods[1].imag());
    }
    std::printf("wrote %s\n", o.output.c_str());
    if (!o.picture.empty()) std::printf("wrote %s\n", o.picture.c_str());
    if (!o.report.empty()) std::printf("wrote %s\n", o.report.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ricci::cli::Options options;
  try {
    options = ricci::cli::parse_options(argc, argv);
  } catch (const ricci::Error& e) {
    std::fprintf(stderr, "ricci-flow: error: %s\n", e.what());
    return 2;
  }
  if (options.help) {
    std::fputs(ricci::cli::usage().c_str(), stdout);
    return 0;
  }
  if (options.version) {
    std::puts("ricci-flow 0.1.0");
    return 0;
  }
  try {
    return run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ricci-flow: error: %s\n", e.what());
    return 1;
  }
}
