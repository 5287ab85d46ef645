#include "ricci/report.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "metric.h"
#include "ricci/atlas.h"

namespace ricci {

namespace {

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

std::string complex_pair(std::complex<double> z) {
  return "[" + number(z.real()) + ", " + number(z.imag()) + "]";
}

std::string layout_json(const Uniformization& run) {
  if (run.layout_kind == LayoutKind::None) return "null";
  const LayoutQuality& q = run.quality;
  const Layout& m = run.layout;
  std::ostringstream j;
  j << "{\"kind\": " << quoted(to_string(run.layout_kind))
    << ", \"flipped_faces\": " << q.flipped_faces << ", \"collapsed_faces\": " << q.collapsed_faces
    << ", \"failure\": " << (run.layout_failure.empty() ? "null" : quoted(run.layout_failure))
    << ", \"quasi_conformal\": {\"median\": " << number(q.quasi_conformal_median)
    << ", \"p95\": " << number(q.quasi_conformal_p95)
    << ", \"max\": " << number(q.quasi_conformal_max) << "}"
    << ", \"area_ratio\": {\"p5\": " << number(q.area_ratio_p5)
    << ", \"median\": " << number(q.area_ratio_median) << ", \"p95\": " << number(q.area_ratio_p95)
    << "}";
  if (run.preset == TargetPreset::UnitDisk) j << ", \"circle_error\": " << number(run.circle_error);
  j << ", \"input_faces_turned_over\": " << run.input_faces_turned_over;
  if (run.subdivision) {
    const CommonSubdivision& sub = *run.subdivision;
    j << ", \"common_subdivision\": {\"vertices\": " << sub.positions.size()
      << ", \"new_vertices\": " << sub.positions.size() - sub.num_input_vertices
      << ", \"faces\": " << sub.faces.size() << ", \"flips_followed\": " << sub.num_flips
      << ", \"disk_splits\": " << sub.disk_splits << ", \"seconds\": " << number(sub.seconds)
      << "}";
  } else {
    j << ", \"common_subdivision\": null";
  }
  if (!run.subdivision_failure.empty()) {
    j << ", \"common_subdivision_failure\": " << quoted(run.subdivision_failure);
  }
  if (run.geometry == Geometry::Euclidean) {
    j << ", \"max_relative_length_error\": " << number(m.max_relative_length_error);
  }
  j << ", \"flipped_faces_of_flow_triangulation\": " << m.num_flipped_faces
    << ", \"closure_error\": " << number(m.closure_error)
    << ", \"relation_error\": " << number(m.relation_error)
    << ", \"cut_paths\": " << m.cut.paths.size() << ", \"generators\": " << m.cut.num_generators;
  if (run.geometry == Geometry::Hyperbolic && m.reach > 0) {
    j << ", \"reach\": " << number(m.reach) << ", \"charts\": " << m.num_charts();
    if (m.num_charts() > 1) j << ", \"chart_radius\": " << number(m.chart_radius);
  }
  if (!run.periods.empty()) {
    j << ", \"periods\": [" << complex_pair(run.periods[0]) << ", " << complex_pair(run.periods[1])
      << "]";
  }
  // E2: z -> a z + b; H2: z -> (a z + b) / (conj(b) z + conj(a)); a and b as [re, im].
  j << ", \"deck_transformations\": [";
  for (size_t k = 0; k < m.deck.size(); ++k) {
    j << (k ? ", " : "") << "{\"a\": " << complex_pair(m.deck[k].a)
      << ", \"b\": " << complex_pair(m.deck[k].b) << "}";
  }
  j << "]}";
  return j.str();
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

std::vector<std::pair<std::string, double>> result_numbers(const Uniformization& run) {
  return {
      {"iterations", run.totals.newton_iterations},
      {"edge_flips", run.totals.edge_flips},
      {"max_curvature_error", run.quality.max_curvature_error},
      {"flipped_faces", run.quality.flipped_faces},
      {"quasi_conformal_median", run.quality.quasi_conformal_median},
      {"closure_error", run.layout.closure_error},
      {"circle_error", run.circle_error},
      {"flows", run.totals.flows},
      {"collapsed_faces", run.quality.collapsed_faces},
      {"input_faces_turned_over", run.input_faces_turned_over},
      {"new_vertices", run.subdivision ? static_cast<double>(run.subdivision->positions.size() -
                                                             run.subdivision->num_input_vertices)
                                       : 0.0}};
}

std::vector<std::string> summary_lines(const MeshUniformization& run, const RunContext& context) {
  std::vector<std::string> lines;
  for (const std::string& line : run.mesh.report.lines()) lines.push_back("Repaired: " + line);
  const size_t n = run.components.size();
  if (n > 1) {
    lines.push_back(std::to_string(n) + " connected components, each mapped by its own topology");
  }
  for (size_t k = 0; k < n; ++k) {
    RunContext c = context;
    if (n > 1)
      c.input += (c.input.empty() ? "" : ", ") + std::string("component ") + std::to_string(k);
    for (const std::string& line :
         summary_lines(run.mesh.components[k].mesh, run.components[k], c)) {
      lines.push_back(line);
    }
  }
  return lines;
}

std::vector<std::pair<std::string, double>> result_numbers(const MeshUniformization& run) {
  if (run.components.size() == 1) return result_numbers(run.components[0]);
  std::vector<std::pair<std::string, double>> total;
  for (const Uniformization& c : run.components) {
    const auto numbers = result_numbers(c);
    if (total.empty()) {
      total = numbers;
      continue;
    }
    for (size_t i = 0; i < numbers.size(); ++i) {
      const std::string& name = numbers[i].first;
      const bool sum = name == "iterations" || name == "edge_flips" || name == "flipped_faces" ||
                       name == "flows" || name == "collapsed_faces" ||
                       name == "input_faces_turned_over" || name == "new_vertices";
      total[i].second =
          sum ? total[i].second + numbers[i].second : std::max(total[i].second, numbers[i].second);
    }
  }
  total.emplace_back("components", static_cast<double>(run.components.size()));
  return total;
}

std::vector<std::string> summary_lines(const CompactMesh& mesh, const Uniformization& run,
                                       const RunContext& context) {
  std::vector<std::string> lines;
  std::ostringstream s;
  s << "Ricci flow" << (context.input.empty() ? "" : " on " + context.input) << ": "
    << mesh.topology_name() << ", " << mesh.num_vertices() << " vertices, " << mesh.num_faces()
    << " faces; " << to_string(run.geometry) << " geometry, " << to_string(run.scheme)
    << " scheme, target " << to_string(run.preset);
  lines.push_back(s.str());
  const auto line = [&](auto&&... parts) {
    std::ostringstream l;
    l.precision(3);
    (l << ... << parts);
    lines.push_back(l.str());
  };
  const FlowTotals& t = run.totals;
  if (!run.converged()) {
    line("Not converged after ", t.newton_iterations, " Newton iterations: ", run.result.failure);
    return lines;
  }
  line("Converged in ", t.newton_iterations, " Newton iterations with ", t.edge_flips,
       " edge flips: max |K - Kbar| = ", run.quality.max_curvature_error, ", mean ",
       run.quality.mean_curvature_error, " (", t.times.total, " s)");
  if (t.attainable_residual > 0) {
    line("The tolerance ", run.tolerance,
         " is below what double precision allows on this metric: ", "converged within ",
         t.attainable_residual, " (10 times the angle sums' round-off)");
  }
  if (!run.scheme_instead.empty()) {
    line("Warning: the ", to_string(run.scheme), " scheme instead of Yamabe: ", run.scheme_instead);
  }
  if (!run.target_instead.empty()) {
    line("Warning: the ", to_string(run.preset),
         " target instead of the automatic one: ", run.target_instead);
  }
  if (t.flips_from_iteration >= 0) {
    line("Edge flips were needed from iteration ", t.flips_from_iteration,
         " on: on the input's triangulation, ", t.without_flips);
  }
  if (run.doubled) {
    line(
        "Flowed on the surface doubled along its boundary, where boundary edges flip too: on "
        "the surface itself the flow ",
        run.doubled_because);
  }
  if (run.preset == TargetPreset::UnitDisk) {
    line("Boundary loops on circles after ", t.flows, " flows: circle error ", run.circle_error);
  }
  if (run.layout_kind == LayoutKind::None) {
    line("No layout: a ", mesh.topology_name(), " in ", to_string(run.geometry),
         " geometry has none here");
    return lines;
  }
  const LayoutQuality& q = run.quality;
  const char* faces = "input's faces";
  if (run.subdivision) {
    const CommonSubdivision& sub = *run.subdivision;
    faces = "subdivision's faces";
    if (run.input_faces_turned_over > 0) {
      line("Common subdivision: ", run.input_faces_turned_over,
           " of the input's faces would turn over on the flipped triangulation, so the input is "
           "cut along its edges: ",
           sub.positions.size(), " vertices (", sub.positions.size() - mesh.num_vertices(),
           " new: on input edges, and any rim splits below), ", sub.faces.size(), " faces (",
           sub.seconds, " s)");
    }
    if (sub.disk_splits > 0) {
      line("Poincare disk drawing: ", sub.disk_splits,
           " sides split on their geodesics (at the midpoint, or for a cap at the foot of the "
           "perpendicular from its third corner; a new vertex each, dividing the side on the "
           "surface alike), as thin faces near the rim turn over when drawn straight: ",
           sub.positions.size(), " vertices, ", sub.faces.size(), " faces");
    }
  } else if (run.input_faces_turned_over > 0 && !run.subdivision_failure.empty()) {
    line("No common subdivision: ", run.subdivision_failure);
  }
  line("Layout (", to_string(run.layout_kind), "): ", q.flipped_faces, " of the ", faces,
       " flipped; quasi-conformal ratio median ", q.quasi_conformal_median, ", 95% ",
       q.quasi_conformal_p95, ", max ", q.quasi_conformal_max, "; area ratio 5%..95% ",
       q.area_ratio_p5, "..", q.area_ratio_p95);
  if (q.collapsed_faces > 0) {
    line("Warning: ", q.collapsed_faces, " of the ", faces,
         " are squeezed to almost no area in "
         "the layout (first: face ",
         q.first_collapsed_face,
         "): the conformal map shrinks "
         "protrusions exponentially");
  }
  if (run.centring_skipped) {
    line("The sphere is not centred: the centring Moebius map would turn faces over");
  }
  if (!run.layout_failure.empty()) line("Invalid layout: ", run.layout_failure);
  const Layout& m = run.layout;
  if (m.num_charts() > 1) {
    line("Poincare disk in ", m.num_charts(), " charts: the domain reaches hyperbolic distance ",
         m.reach,
         " from its centre, where double precision no longer draws its faces in one disk; ",
         "each chart is a piece of it moved within ", m.chart_radius,
         " of a disk's centre, the disks side by side in the texture (no deck transformations)");
  }
  if (!m.cut.paths.empty()) {
    line("Cut into a disk along ", m.cut.paths.size(), " paths (", m.cut.num_generators,
         " generators): closure error ", m.closure_error, ", relation error ", m.relation_error);
  }
  if (!run.periods.empty()) {
    line("Flat torus: periods (", run.periods[0].real(), ", ", run.periods[0].imag(), ") and (",
         run.periods[1].real(), ", ", run.periods[1].imag(), ")");
  }
  return lines;
}

namespace {

// The keys of one component's report, one per line, without the braces.
std::string component_json_body(const CompactMesh& mesh, const Uniformization& run,
                                const RunContext& context) {
  const FlowResult& result = run.result;
  const FlowTotals& totals = run.totals;
  const FlowTimes& t = totals.times;
  const LayoutQuality& q = run.quality;
  std::ostringstream j;
  j << "  \"input\": " << quoted(context.input) << ",\n";
  j << "  \"mesh\": {\"vertices\": " << mesh.num_vertices() << ", \"faces\": " << mesh.num_faces()
    << ", \"edges\": " << mesh.num_edges()
    << ", \"euler_characteristic\": " << mesh.euler_characteristic()
    << ", \"genus\": " << mesh.genus() << ", \"boundary_loops\": " << mesh.num_boundary_loops()
    << ", \"topology\": " << quoted(mesh.topology_name()) << "},\n";
  j << "  \"geometry\": " << quoted(to_string(run.geometry)) << ",\n";
  j << "  \"scheme\": " << quoted(to_string(run.scheme)) << ",\n";
  j << "  \"target\": " << quoted(context.target) << ",\n";
  j << "  \"preset\": " << quoted(to_string(run.preset)) << ",\n";
  j << "  \"tolerance\": " << number(run.tolerance) << ",\n";
  j << "  \"length_scale\": " << number(run.structure.length_scale) << ",\n";
  j << "  \"converged\": " << (result.converged ? "true" : "false") << ",\n";
  j << "  \"failure\": " << (result.converged ? "null" : quoted(result.failure)) << ",\n";
  j << "  \"residual\": " << number(result.residual) << ",\n";
  j << "  \"attainable_residual\": "
    << (totals.attainable_residual > 0 ? number(totals.attainable_residual) : "null") << ",\n";
  const bool needed = totals.flips_from_iteration >= 0;
  j << "  \"edge_flips_needed\": " << (needed ? "true" : "false") << ",\n";
  j << "  \"flips_from_iteration\": "
    << (needed ? std::to_string(totals.flips_from_iteration) : "null") << ",\n";
  j << "  \"without_flips\": " << (needed ? quoted(totals.without_flips) : "null") << ",\n";
  j << "  \"target_instead\": "
    << (run.target_instead.empty() ? "null" : quoted(run.target_instead)) << ",\n";
  j << "  \"scheme_instead\": "
    << (run.scheme_instead.empty() ? "null" : quoted(run.scheme_instead)) << ",\n";
  j << "  \"doubled_surface\": " << (run.doubled ? "true" : "false") << ",\n";
  j << "  \"flows\": " << totals.flows << ",\n";
  j << "  \"iterations\": " << totals.newton_iterations << ",\n";
  j << "  \"edge_flips\": " << totals.edge_flips << ",\n";
  j << "  \"symbolic_analyses\": " << totals.symbolic_analyses << ",\n";
  j << "  \"numeric_factorizations\": " << totals.numeric_factorizations << ",\n";
  j << "  \"krylov_iterations\": " << totals.krylov_iterations << ",\n";
  j << "  \"last_flow\": {\"iterations\": " << result.iterations
    << ", \"residual_history\": " << array(result.residual_history)
    << ", \"step_history\": " << array(result.step_history)
    << ", \"edge_flips\": " << result.num_flips
    << ", \"connectivity_changes\": " << result.connectivity_changes << "},\n";
  j << "  \"seconds\": {\"read\": " << number(context.read_seconds)
    << ", \"setup\": " << number(t.setup) << ", \"assembly\": " << number(t.assembly)
    << ", \"analysis\": " << number(t.analysis)
    << ", \"factorization\": " << number(t.factorization) << ", \"solve\": " << number(t.solve)
    << ", \"line_search\": " << number(t.line_search) << ", \"flips\": " << number(t.flips)
    << ", \"flows\": " << number(t.total) << "},\n";
  j << "  \"errors\": {\"max_abs_curvature_error\": " << number(q.max_curvature_error)
    << ", \"mean_abs_curvature_error\": " << number(q.mean_curvature_error)
    << ", \"gauss_bonnet_error\": " << number(gauss_bonnet_error(mesh, run.geometry, result))
    << ", \"initial_length_error\": " << number(initial_length_error(mesh, run.structure))
    << "},\n";
  j << "  \"area\": " << number(result.area) << ",\n";
  j << "  \"layout\": " << layout_json(run);
  return j.str();
}

std::string repairs_json(const RepairReport& report) {
  std::string a = "[";
  for (size_t k = 0; k < report.entries.size(); ++k) {
    const RepairReport::Entry& e = report.entries[k];
    std::string first;
    for (size_t i = 0; i < e.first.size(); ++i)
      first += (i ? ", " : "") + std::to_string(e.first[i]);
    a += (k ? ", " : "") + std::string("{\"what\": ") + quoted(e.what) +
         ", \"element\": " + quoted(e.element) + ", \"count\": " + std::to_string(e.count) +
         ", \"first\": [" + first + "]}";
  }
  return a + "]";
}

std::string indented(const std::string& text) {
  std::string out;
  for (char c : text) {
    out += c;
    if (c == '\n') out += "  ";
  }
  return out;
}

}  // namespace

std::string json_report(const CompactMesh& mesh, const Uniformization& run,
                        const RunContext& context) {
  return "{\n" + component_json_body(mesh, run, context) + "\n}\n";
}

std::string json_report(const MeshUniformization& run, const RunContext& context) {
  const RepairedMesh& m = run.mesh;
  if (run.components.size() == 1) {
    return "{\n" + component_json_body(m.components[0].mesh, run.components[0], context) +
           ",\n  \"repairs\": " + repairs_json(m.report) + "\n}\n";
  }
  std::ostringstream j;
  j << "{\n";
  j << "  \"input\": " << quoted(context.input) << ",\n";
  j << "  \"converged\": " << (run.converged() ? "true" : "false") << ",\n";
  j << "  \"repairs\": " << repairs_json(m.report) << ",\n";
  j << "  \"components\": [";
  for (size_t k = 0; k < run.components.size(); ++k) {
    j << (k ? ", " : "") << "{\n  "
      << indented(component_json_body(m.components[k].mesh, run.components[k], context)) << "\n  }";
  }
  j << "]\n}\n";
  return j.str();
}

}  // namespace ricci
