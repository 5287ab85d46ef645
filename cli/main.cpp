// ricci-flow: the unified discrete surface Ricci flow on one mesh, from the command line.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include <Eigen/Geometry>

#include "options.h"
#include "picture.h"
#include "report.h"
#include "result_ply.h"
#include "ricci/errors.h"
#include "ricci/layout.h"
#include "ricci/mesh_io.h"
#include "ricci/model_layout.h"
#include "ricci/ricci_flow.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

ricci::TargetCurvature make_target(const std::string& spec, const ricci::CompactMesh& mesh) {
  using ricci::TargetCurvature;
  if (spec == "auto") return TargetCurvature::automatic(mesh);
  if (spec == "zero") return TargetCurvature::zero(mesh);
  if (spec == "free-boundary") {
    if (mesh.is_closed()) {
      throw ricci::InvalidTargetError(
          "--target free-boundary needs a boundary, but the mesh is a " + mesh.topology_name() +
          "; use --target zero");
    }
    return TargetCurvature::free_boundary(mesh);
  }
  const std::vector<double> values = ricci::cli::read_numbers(spec);
  return TargetCurvature::from_values(
      mesh, Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<long>(values.size())));
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
  VcgMesh vcg_mesh;
  read_mesh(o.input, vcg_mesh);
  CompactMesh mesh = [&] {
    try {
      return compact_mesh_from_vcg(vcg_mesh);
    } catch (const InvalidMeshError& e) {
      throw InvalidMeshError(o.input + ": " + e.what());
    }
  }();
  const double read_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();

  const Geometry geometry =
      o.geometry == "auto" ? automatic_geometry(mesh) : geometry_from_string(o.geometry);
  SchemeOptions scheme;
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
  if (!o.picture.empty() && !(geometry == Geometry::Euclidean && mesh.is_disk())) {
    throw InvalidArgumentError(
        "--picture needs a planar layout (euclidean geometry on a disk); "
        "this run is " +
        to_string(geometry) + " on a " + mesh.topology_name());
  }
  const TargetCurvature target = make_target(o.target, mesh);
  const ConformalStructure structure = prepare_flow(mesh, geometry, scheme, target);

  FlowOptions flow;
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
  const FlowResult result = run_ricci_flow(mesh, structure, target, flow);
  if (show_progress) std::fprintf(stderr, "\n");

  cli::RunSummary summary;
  summary.input = o.input;
  summary.geometry = geometry;
  summary.scheme = scheme.scheme;
  summary.target = o.target;
  summary.tolerance = o.tolerance;
  summary.length_scale = structure.length_scale;
  summary.initial_length_error = cli::initial_length_error(mesh, structure);
  summary.read_seconds = read_seconds;

  PlanarLayout layout;
  cli::ResultLayout written;
  const bool planar = result.converged && geometry == Geometry::Euclidean && mesh.is_disk();
  if (planar) {
    layout =
        layout_disk(result_triangulation(mesh, result), result.edge_lengths, flow.linear_solver);
    summary.layout = &layout;
    summary.flipped_input_faces = count_flipped_faces(mesh, layout.position);
    for (const auto& p : layout.position) written.position.emplace_back(p.x(), p.y(), 0.0);
    written.texture = normalized_texture_coordinates(layout.position);
  }
  ModelLayout model;
  if (result.converged && !planar) {
    const Triangulation flowed = result_triangulation(mesh, result);
    model = develop(flowed, geometry, result.edge_lengths);
    summary.model_layout = &model;
    if (geometry == Geometry::Spherical && mesh.is_closed() && mesh.genus() == 0) {
      written.position = center_on_sphere(vertex_positions(flowed, model));
      for (const auto& f : mesh.faces()) {
        const auto& x = written.position;
        summary.flipped_input_faces += !(x[f[0]].dot(x[f[1]].cross(x[f[2]])) > 0);
      }
    } else if (geometry != Geometry::Spherical) {
      written.wedge_texture =
          cli::wedge_texture_coordinates(geometry, corners_on(flowed, model, mesh));
      for (const auto& w : written.wedge_texture) {
        const Eigen::Vector2d a = w[1] - w[0], b = w[2] - w[0];
        summary.flipped_input_faces += !(a.x() * b.y() - a.y() * b.x() > 0);
      }
    }
  }
  if (!o.report.empty()) cli::write_report(o.report, mesh, summary, result);
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
    if (planar) {
      std::printf("layout: %d of the input's faces flipped, max relative length error %.2e\n",
                  summary.flipped_input_faces, layout.max_relative_length_error);
    } else if (summary.model_layout) {
      std::printf(
          "layout in the %s: %d of the input's faces flipped, %zu cut paths, closure "
          "error %.2e\n",
          geometry == Geometry::Spherical    ? "unit sphere"
          : geometry == Geometry::Hyperbolic ? "Poincare disk"
                                             : "plane, cut open",
          summary.flipped_input_faces, model.cut.paths.size(), model.closure_error);
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
