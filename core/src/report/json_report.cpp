// json_report (report.h): the run, its components and repairs as JSON.
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "ricci/pipeline/atlas.h"
#include "ricci/report/report.h"

namespace ricci {

namespace {

// The length of the well-formed UTF-8 sequence at s[i] (RFC 3629: no overlong forms, no
// surrogates, nothing past U+10FFFF), or 0.
size_t utf8_length(const std::string& s, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b = byte(i);
  size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // the second byte's range
  if (b < 0x80) return 1;
  if (b >= 0xC2 && b <= 0xDF) n = 2;
  if (b >= 0xE0 && b <= 0xEF) n = 3, lo = b == 0xE0 ? 0xA0 : 0x80, hi = b == 0xED ? 0x9F : 0xBF;
  if (b >= 0xF0 && b <= 0xF4) n = 4, lo = b == 0xF0 ? 0x90 : 0x80, hi = b == 0xF4 ? 0x8F : 0xBF;
  if (n == 0 || i + n > s.size() || byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (size_t k = 2; k < n; ++k) {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  }
  return n;
}

// A JSON string of any bytes: UTF-8 as it is, control characters escaped, and each byte that is
// no part of a well-formed UTF-8 sequence (a file name in another encoding) as U+FFFD.
std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const size_t n = utf8_length(s, i);
    if (c == '"' || c == '\\') {
      q += '\\';
      q += static_cast<char>(c);
    } else if (c < 0x20) {
      const char* hex = "0123456789abcdef";
      q += "\\u00";
      q += hex[c >> 4];
      q += hex[c & 15];
    } else if (n == 0) {
      q += "\\ufffd";
      i += 1;
      continue;
    } else {
      q.append(s, i, n);
      i += n;
      continue;
    }
    i += 1;
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

// `vertex`: the delivered vertex of each of the component's vertices (null: the same numbers).
std::string layout_json(const Uniformization& run, const std::vector<int>* vertex) {
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
  if (std::isfinite(run.input_faces_qc_p95)) {
    j << ", \"input_faces_qc_p95\": " << number(run.input_faces_qc_p95);
  }
  if (run.subdivision) {
    const CommonSubdivision& sub = *run.subdivision;
    j << ", \"common_subdivision\": {\"vertices\": " << sub.positions.size()
      << ", \"new_vertices\": " << sub.positions.size() - sub.num_input_vertices
      << ", \"faces\": " << sub.faces.size() << ", \"flips_followed\": " << sub.num_flips
      << ", \"disk_splits\": " << sub.disk_splits
      << ", \"on_drawn_sides\": " << (sub.on_drawn_sides ? "true" : "false")
      << ", \"drawn_side_corners\": " << sub.drawn_side_corners
      << ", \"seconds\": " << number(sub.seconds) << "}";
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
  if (run.layout_kind == LayoutKind::Atlas) {
    const AtlasResult& a = run.atlas;
    const ConePlacement& p = a.placement;
    j << ", \"atlas\": {\"cones\": [";
    for (size_t k = 0; k < p.cones.size(); ++k) {
      const int v = p.cones[k].vertex;
      j << (k ? ", " : "") << "{\"vertex\": " << (vertex ? (*vertex)[static_cast<size_t>(v)] : v)
        << ", \"angle\": " << number(k < a.cone_angles.size() ? a.cone_angles[k] : p.cones[k].angle)
        << ", \"linear_angle\": " << number(p.cones[k].angle) << "}";
    }
    j << "], \"user_cones\": " << (a.user_cones ? "true" : "false") << ", \"unfolded\": "
      << (a.unfolded == AtlasResult::Unfolded::No ? "null" : quoted(to_string(a.unfolded)))
      << ", \"loops\": " << (a.loops ? "true" : "false")
      << ", \"held_curvatures\": " << (a.held_curvatures ? "true" : "false")
      << ", \"distortion\": " << number(a.distortion)
      << ", \"vertex_distortion\": " << number(a.flow_distortion)
      << ", \"linear_distortion\": " << number(p.distortion)
      << ", \"distortion_without_cones\": " << number(p.distortion_without_cones)
      << ", \"bound\": " << number(a.bound) << ", \"bound_asked\": " << number(a.bound_asked)
      << ", \"bound_instead\": " << (a.bound_instead.empty() ? "null" : quoted(a.bound_instead))
      << ", \"bound_reached\": " << (p.bound_reached ? "true" : "false")
      << ", \"max_deviation\": " << number(p.max_deviation)
      << ", \"placement\": {\"factorizations\": " << p.factorizations
      << ", \"back_solves\": " << p.back_solves << ", \"relocations\": " << p.relocations
      << ", \"dropped\": " << p.dropped
      << ", \"least_distortion\": " << (p.least_distortion ? "true" : "false")
      << ", \"seconds\": " << number(p.seconds) << "}"
      << ", \"charts\": " << a.num_charts << ", \"splits\": " << a.splits
      << ", \"harmonic_charts\": " << a.harmonic_charts
      << ", \"on_input_faces\": " << (a.on_input_faces ? "true" : "false")
      << ", \"untangled_vertices\": " << a.untangled
      << ", \"input_faces_cut\": " << a.input_faces_cut
      << ", \"seam_length\": " << number(a.seam_length) << ", \"seam_edges\": " << a.seam_edges
      << ", \"overlapping_faces\": " << a.overlapping_faces
      << ", \"utilization\": " << number(a.utilization) << ", \"padding\": " << number(a.padding)
      << ", \"charts_below_a_texel\": "
      << (std::isfinite(a.utilization) ? std::to_string(a.charts_below_a_texel) : "null")
      << ", \"seconds\": {\"charts\": " << number(a.seconds.charts)
      << ", \"harmonic\": " << number(a.seconds.harmonic)
      << ", \"packing\": " << number(a.seconds.packing) << "}}";
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

namespace {

// The keys of one component's report, one per line, without the braces; vertices numbered as
// delivered (`vertex`, as layout_json's).
std::string component_json_body(const CompactMesh& mesh, const Uniformization& run,
                                const RunContext& context,
                                const std::vector<int>* vertex = nullptr) {
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
  j << "  \"doubled_because\": " << (run.doubled ? quoted(run.doubled_because) : "null") << ",\n";
  j << "  \"double_failure\": "
    << (run.double_failure.empty() ? "null" : quoted(run.double_failure)) << ",\n";
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
    << ", \"connectivity_changes\": " << result.connectivity_changes
    << ", \"eased_start_vertices\": " << result.eased_start_vertices
    << ", \"start_jumps\": " << result.start_jumps
    << ", \"start_share\": " << number(result.start_share)
    << ", \"delaunay_class\": " << (result.delaunay_class ? "true" : "false")
    << ", \"input_class_because\": "
    << (result.input_class_because.empty() ? "null" : quoted(result.input_class_because)) << "},\n";
  j << "  \"seconds\": {\"read\": " << number(context.read_seconds)
    << ", \"setup\": " << number(t.setup) << ", \"assembly\": " << number(t.assembly)
    << ", \"analysis\": " << number(t.analysis)
    << ", \"factorization\": " << number(t.factorization) << ", \"solve\": " << number(t.solve)
    << ", \"line_search\": " << number(t.line_search) << ", \"flips\": " << number(t.flips)
    << ", \"flows\": " << number(t.total) << ", \"uniformization\": " << number(run.seconds)
    << "},\n";
  j << "  \"errors\": {\"max_abs_curvature_error\": " << number(q.max_curvature_error)
    << ", \"mean_abs_curvature_error\": " << number(q.mean_curvature_error)
    << ", \"gauss_bonnet_error\": " << number(gauss_bonnet_error(mesh, run.geometry, result))
    << ", \"initial_length_error\": " << number(initial_length_error(mesh, run.structure))
    << "},\n";
  j << "  \"area\": " << number(result.area) << ",\n";
  j << "  \"layout\": " << layout_json(run, vertex);
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
    return "{\n" +
           component_json_body(m.components[0].mesh, run.components[0], context,
                               &m.components[0].vertex) +
           ",\n  \"repairs\": " + repairs_json(m.report) + "\n}\n";
  }
  std::ostringstream j;
  j << "{\n";
  j << "  \"input\": " << quoted(context.input) << ",\n";
  j << "  \"converged\": " << (run.converged() ? "true" : "false") << ",\n";
  j << "  \"repairs\": " << repairs_json(m.report) << ",\n";
  if (run.packed.pieces > 0) {
    j << "  \"texture\": {\"pieces\": " << run.packed.pieces
      << ", \"utilization\": " << number(run.packed.utilization)
      << ", \"padding\": " << number(run.packed.padding)
      << ", \"below_a_texel\": " << run.packed.below_a_texel
      << ", \"distortion\": " << number(run.packed.distortion) << "},\n";
  }
  j << "  \"components\": [";
  for (size_t k = 0; k < run.components.size(); ++k) {
    j << (k ? ", " : "") << "{\n  "
      << indented(component_json_body(m.components[k].mesh, run.components[k], context,
                                      &m.components[k].vertex))
      << "\n  }";
  }
  j << "]\n}\n";
  return j.str();
}

}  // namespace ricci
