#include "report.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "ricci/errors.h"
#include "metric.h"

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

namespace {

std::string layout_json(const Uniformization& u) {
  if (u.layout == LayoutKind::None) return "null";
  const LayoutQuality& q = u.quality;
  std::ostringstream j;
  j << "{\"kind\": " << quoted(to_string(u.layout)) << ", \"flipped_faces\": " << q.flipped_faces
    << ", \"quasi_conformal\": {\"median\": " << number(q.quasi_conformal_median)
    << ", \"p95\": " << number(q.quasi_conformal_p95)
    << ", \"max\": " << number(q.quasi_conformal_max) << "}"
    << ", \"area_ratio\": {\"p5\": " << number(q.area_ratio_p5)
    << ", \"median\": " << number(q.area_ratio_median) << ", \"p95\": " << number(q.area_ratio_p95)
    << "}";
  if (u.preset == TargetPreset::UnitDisk) {
    j << ", \"circle_error\": " << number(u.circle_error);
  }
  if (!u.model) {
    j << ", \"max_relative_length_error\": " << number(u.max_relative_length_error) << "}";
    return j.str();
  }
  const ModelLayout& m = *u.model;
  j << ", \"flipped_faces_of_flow_triangulation\": " << m.num_flipped_faces
    << ", \"closure_error\": " << number(m.closure_error)
    << ", \"relation_error\": " << number(u.relation_error)
    << ", \"cut_paths\": " << m.cut.paths.size() << ", \"generators\": " << m.cut.num_generators;
  if (!u.periods.empty()) {
    j << ", \"periods\": [[" << number(u.periods[0].real()) << ", " << number(u.periods[0].imag())
      << "], [" << number(u.periods[1].real()) << ", " << number(u.periods[1].imag()) << "]]";
  }
  j << ", \"deck_transformations\": [";
  // E2: z -> a z + b; H2: z -> (a z + b) / (conj(b) z + conj(a)); a and b as [re, im].
  for (size_t k = 0; k < m.deck.size(); ++k) {
    const DiskIsometry& d = m.deck[k];
    j << (k ? ", " : "") << "{\"a\": [" << number(d.a.real()) << ", " << number(d.a.imag())
      << "], \"b\": [" << number(d.b.real()) << ", " << number(d.b.imag()) << "]}";
  }
  j << "]}";
  return j.str();
}

}  // namespace

void write_report(const std::string& path, const CompactMesh& mesh, const RunSummary& run,
                  const Uniformization& u) {
  const FlowResult& result = u.result;
  const LayoutQuality& q = u.quality;
  const FlowTimes& t = result.times;
  std::ostringstream j;
  j << "{\n";
  j << "  \"input\": " << quoted(run.input) << ",\n";
  j << "  \"mesh\": {\"vertices\": " << mesh.num_vertices() << ", \"faces\": " << mesh.num_faces()
    << ", \"edges\": " << mesh.num_edges()
    << ", \"euler_characteristic\": " << mesh.euler_characteristic()
    << ", \"genus\": " << mesh.genus() << ", \"boundary_loops\": " << mesh.num_boundary_loops()
    << ", \"topology\": " << quoted(mesh.topology_name()) << "},\n";
  j << "  \"geometry\": " << quoted(to_string(u.geometry)) << ",\n";
  j << "  \"scheme\": " << quoted(to_string(run.scheme)) << ",\n";
  j << "  \"target\": " << quoted(run.target) << ",\n";
  j << "  \"preset\": " << quoted(to_string(u.preset)) << ",\n";
  j << "  \"tolerance\": " << number(run.tolerance) << ",\n";
  j << "  \"length_scale\": " << number(u.structure.length_scale) << ",\n";
  j << "  \"converged\": " << (result.converged ? "true" : "false") << ",\n";
  j << "  \"failure\": " << (result.converged ? "null" : quoted(result.failure)) << ",\n";
  j << "  \"iterations\": " << result.iterations << ",\n";
  j << "  \"boundary_iterations\": " << u.boundary_iterations << ",\n";
  j << "  \"newton_iterations\": " << u.newton_iterations << ",\n";
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
  j << "  \"errors\": {\"max_abs_curvature_error\": " << number(q.max_curvature_error)
    << ", \"mean_abs_curvature_error\": " << number(q.mean_curvature_error)
    << ", \"gauss_bonnet_error\": " << number(gauss_bonnet_error(mesh, u.geometry, result))
    << ", \"initial_length_error\": " << number(run.initial_length_error) << "},\n";
  j << "  \"area\": " << number(result.area) << ",\n";
  j << "  \"layout\": " << layout_json(u) << "\n";
  j << "}\n";
  std::ofstream out(path);
  if (!out) throw IoError("cannot write report '" + path + "'");
  out << j.str();
  if (!out) throw IoError("writing report '" + path + "' failed");
}

}  // namespace ricci::cli
