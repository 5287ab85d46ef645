#include "report.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "ricci/errors.h"
#include "ricci/metric.h"

namespace ricci::cli {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      q += '\\';
      q += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      q += ' ';
    } else {
      q += c;
    }
  }
  return q + "\"";
}

std::string number(double x) {
  if (!std::isfinite(x)) return "null";
  std::ostringstream s;
  s.precision(std::numeric_limits<double>::max_digits10);
  s << x;
  return s.str();
}

std::string array(const std::vector<double>& xs) {
  std::string a = "[";
  for (size_t i = 0; i < xs.size(); ++i) a += (i ? ", " : "") + number(xs[i]);
  return a + "]";
}

}  // namespace

double initial_length_error(const CompactMesh& mesh, const ConformalStructure& structure) {
  const MetricState state = evaluate_metric(mesh, structure, structure.u0);
  double err = 0;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const double want = structure.length_scale * mesh.input_lengths()[e];
    const double got = state.edges[e].valid ? state.edges[e].length : INFINITY;
    err = std::max(err, std::abs(got / want - 1));
  }
  return err;
}

double gauss_bonnet_error(const CompactMesh& mesh, Geometry geometry, const FlowResult& result) {
  return result.curvature.sum() + background_curvature(geometry) * result.area -
         2 * kPi * mesh.euler_characteristic();
}

void write_report(const std::string& path, const CompactMesh& mesh, const RunSummary& run,
                  const FlowResult& result) {
  double max_err = 0, sum_err = 0;
  int counted = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (std::isnan(result.target[v])) continue;
    const double e = std::abs(result.curvature[v] - result.target[v]);
    max_err = std::max(max_err, e);
    sum_err += e;
    ++counted;
  }
  const FlowTimes& t = result.times;
  std::ostringstream j;
  j << "{\n";
  j << "  \"input\": " << quoted(run.input) << ",\n";
  j << "  \"mesh\": {\"vertices\": " << mesh.num_vertices() << ", \"faces\": " << mesh.num_faces()
    << ", \"edges\": " << mesh.num_edges()
    << ", \"euler_characteristic\": " << mesh.euler_characteristic()
    << ", \"genus\": " << mesh.genus() << ", \"boundary_loops\": " << mesh.num_boundary_loops()
    << ", \"topology\": " << quoted(mesh.topology_name()) << "},\n";
  j << "  \"geometry\": " << quoted(to_string(run.geometry)) << ",\n";
  j << "  \"scheme\": " << quoted(to_string(run.scheme)) << ",\n";
  j << "  \"target\": " << quoted(run.target) << ",\n";
  j << "  \"tolerance\": " << number(run.tolerance) << ",\n";
  j << "  \"length_scale\": " << number(run.length_scale) << ",\n";
  j << "  \"converged\": " << (result.converged ? "true" : "false") << ",\n";
  j << "  \"failure\": " << (result.converged ? "null" : quoted(result.failure)) << ",\n";
  j << "  \"iterations\": " << result.iterations << ",\n";
  j << "  \"residual\": " << number(result.residual) << ",\n";
  j << "  \"residual_history\": " << array(result.residual_history) << ",\n";
  j << "  \"step_history\": " << array(result.step_history) << ",\n";
  j << "  \"edge_flips\": " << result.num_flips << ",\n";
  j << "  \"connectivity_changes\": " << result.connectivity_changes << ",\n";
  j << "  \"symbolic_analyses\": " << result.num_analyses << ",\n";
  j << "  \"numeric_factorizations\": " << result.num_factorizations << ",\n";
  j << "  \"seconds\": {\"read\": " << number(run.read_seconds)
    << ", \"setup\": " << number(t.setup) << ", \"assembly\": " << number(t.assembly)
    << ", \"analysis\": " << number(t.analysis)
    << ", \"factorization\": " << number(t.factorization) << ", \"solve\": " << number(t.solve)
    << ", \"line_search\": " << number(t.line_search) << ", \"flips\": " << number(t.flips)
    << ", \"flow_total\": " << number(t.total) << "},\n";
  j << "  \"errors\": {\"max_abs_curvature_error\": " << number(max_err)
    << ", \"mean_abs_curvature_error\": " << number(counted ? sum_err / counted : 0.0)
    << ", \"gauss_bonnet_error\": " << number(gauss_bonnet_error(mesh, run.geometry, result))
    << ", \"initial_length_error\": " << number(run.initial_length_error) << "},\n";
  j << "  \"area\": " << number(result.area) << ",\n";
  if (run.layout) {
    j << "  \"layout\": {\"kind\": \"plane\", \"flipped_faces\": " << run.flipped_input_faces
      << ", \"flipped_faces_of_flow_triangulation\": " << run.layout->num_flipped_faces
      << ", \"max_relative_length_error\": " << number(run.layout->max_relative_length_error)
      << "}\n";
  } else if (run.model_layout) {
    const ModelLayout& m = *run.model_layout;
    const char* kind = m.geometry == Geometry::Spherical    ? "sphere"
                       : m.geometry == Geometry::Hyperbolic ? "poincare-disk"
                                                            : "plane-cut";
    j << "  \"layout\": {\"kind\": \"" << kind
      << "\", \"flipped_faces\": " << run.flipped_input_faces
      << ", \"flipped_faces_of_flow_triangulation\": " << m.num_flipped_faces
      << ", \"closure_error\": " << number(m.closure_error)
      << ", \"cut_paths\": " << m.cut.paths.size() << ", \"generators\": " << m.cut.num_generators
      << ", \"deck_transformations\": [";
    // E2: z -> a z + b; H2: z -> (a z + b) / (conj(b) z + conj(a)); a and b as [re, im].
    for (size_t k = 0; k < m.deck.size(); ++k) {
      const DiskIsometry& d = m.deck[k];
      j << (k ? ", " : "") << "{\"a\": [" << number(d.a.real()) << ", " << number(d.a.imag())
        << "], \"b\": [" << number(d.b.real()) << ", " << number(d.b.imag()) << "]}";
    }
    j << "]}\n";
  } else {
    j << "  \"layout\": null\n";
  }
  j << "}\n";
  std::ofstream out(path);
  if (!out) throw IoError("cannot write report '" + path + "'");
  out << j.str();
  if (!out) throw IoError("writing report '" + path + "' failed");
}

}  // namespace ricci::cli
