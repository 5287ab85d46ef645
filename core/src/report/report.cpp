#include "ricci/report/report.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "flow/metric.h"
#include "ricci/pipeline/atlas.h"

namespace ricci {

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

// Said where the charts are packed nearer than the padding asked (Packing::padding); "" where not.
std::string padding_warning(double padding, double asked) {
  if (!(padding < asked * (1 - 1e-9))) return "";
  std::ostringstream s;
  s.precision(3);
  s << "Warning: the charts are " << padding << " texels apart at least, where " << asked
    << " were asked: the texture is too small for so many charts at that padding (a larger "
       "texture size or a smaller padding keeps them apart)";
  return s.str();
}

// Said where charts are packed into less than a texel ("" where none is).
std::string below_a_texel_warning(int below, int charts, const char* what) {
  if (below == 0) return "";
  std::ostringstream s;
  s << "Warning: " << below << " of the " << charts << " " << what
    << " are packed into less than a texel each: the texture draws none of their faces (parts "
       "of the mesh far smaller than the rest, or charts the cones squeeze; a larger texture size "
       "draws more of them)";
  return s.str();
}

}  // namespace

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
    c.packed_together = run.packed.pieces > 0;
    if (n > 1)
      c.input += (c.input.empty() ? "" : ", ") + std::string("component ") + std::to_string(k);
    for (const std::string& line :
         summary_lines(run.mesh.components[k].mesh, run.components[k], c)) {
      lines.push_back(line);
    }
  }
  if (run.packed.pieces > 0) {
    std::ostringstream l;
    l.precision(3);
    l << "Texture of all " << n << " components: area distortion D " << run.packed.distortion
      << " on all its faces; " << run.packed.pieces << " pieces packed, utilization "
      << run.packed.utilization;
    lines.push_back(l.str());
    const std::string padding = padding_warning(run.packed.padding, run.packed.padding_asked);
    if (!padding.empty()) lines.push_back(padding);
    const std::string tiny =
        below_a_texel_warning(run.packed.below_a_texel, run.packed.pieces, "pieces");
    if (!tiny.empty()) lines.push_back(tiny);
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
  if (run.result.delaunay_class) {
    line(
        "Discrete conformal class: the input metric's intrinsic Delaunay triangulation's (the "
        "input flipped to it isometrically before the flow's flips)");
  } else if (!run.result.input_class_because.empty()) {
    line("Discrete conformal class: the input triangulation's, as ",
         run.result.input_class_because);
  }
  if (run.doubled) {
    line(
        "Flowed on the surface doubled along its boundary, where boundary edges flip too: on "
        "the surface itself the flow ",
        run.doubled_because);
  }
  // (Where the surface's flows failed too, their failure names the double's already.)
  if (!run.double_failure.empty() && run.result.converged) {
    line(run.preset == TargetPreset::UnitDisk
             ? "The surface doubled along its boundary, flowed first where the one solve stalled "
               "at the boundary's triangles, gave no map: "
             : "Its class is not its double's (the canonical one), whose flow gave no map: ",
         run.double_failure);
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
           " new: on input edges, inside input faces where the input's Delaunay triangulation "
           "crosses the final one, and any rim splits below), ",
           sub.faces.size(), " faces (", sub.seconds, " s)");
    } else if (std::isfinite(run.input_faces_qc_p95)) {
      line(
          "Common subdivision: the input's faces drawn by their corners on the flipped "
          "triangulation turn none over, but are farther from conformal (quasi-conformal ratio "
          "95% ",
          run.input_faces_qc_p95,
          ") than the pieces of the input and the final triangulation cut together, so the "
          "input is cut along its edges: ",
          sub.positions.size(), " vertices (", sub.positions.size() - mesh.num_vertices(),
          " new), ", sub.faces.size(), " faces (", sub.seconds, " s)");
    }
    if (sub.disk_splits > 0) {
      line("Poincare disk drawing: ", sub.disk_splits,
           " sides split on their geodesics (at the midpoint, or for a cap at the foot of the "
           "perpendicular from its third corner; a new vertex each, dividing the side on the "
           "surface alike), as thin faces near the rim turn over when drawn straight: ",
           sub.positions.size(), " vertices, ", sub.faces.size(), " faces");
    }
    if (!sub.on_drawn_sides && sub.drawn_side_corners > 0) {
      line("Poincare disk texture: ", sub.drawn_side_corners,
           " corners of new vertices drawn on their faces' straight sides (split geodesic pieces "
           "near the rim still turned over as drawn); the layout's model corners keep them on "
           "the geodesics, where the two sides of the cut glue under the deck transformations");
    }
    if (sub.on_drawn_sides) {
      line(
          "Poincare disk texture: new vertices drawn on their faces' straight sides (split "
          "geodesic pieces near a chart's rim still turned over as drawn); the layout's model "
          "corners keep them on the geodesics, where the two sides of the cut glue under the "
          "deck transformations");
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
  if (run.layout_kind == LayoutKind::Atlas) {
    const AtlasResult& a = run.atlas;
    const ConePlacement& p = a.placement;
    // The surface unfolded, the user's cones, or cones placed on the linear model at that cost.
    std::ostringstream cones;
    cones.precision(3);
    cones << p.cones.size() << (p.cones.size() == 1 ? " cone" : " cones");
    if (a.unfolded != AtlasResult::Unfolded::No) {
      cones << ", every interior vertex of curvature (the surface unfolded); area distortion D "
            << a.distortion << " on the faces";
    } else if (a.user_cones) {
      cones << ", yours; area distortion D " << a.distortion << " on the faces ("
            << a.flow_distortion << " at the vertices)";
    } else {
      cones << " (" << p.factorizations
            << (p.factorizations == 1 ? " factorization, " : " factorizations, ") << p.back_solves
            << " back-solves, " << p.seconds << " s), area distortion D " << a.distortion
            << " on the faces (" << a.flow_distortion << " at the vertices, the linear model's "
            << p.distortion;
      // A closed surface but a torus has no flat metric without cones: no D to name.
      if (std::isfinite(p.distortion_without_cones)) {
        cones << "; without cones " << p.distortion_without_cones;
      }
      cones << "), max |u - mean u| " << p.max_deviation;
    }
    std::ostringstream harmonic;
    if (a.on_input_faces || a.input_faces_cut > 0) {
      harmonic << "; drawn on the common subdivision, delivered on your faces";
      if (a.input_faces_cut > 0) {
        harmonic << " but " << a.input_faces_cut
                 << (a.input_faces_cut == 1 ? " cut into its pieces" : " cut into their pieces");
      }
      if (a.harmonic_charts > 0) harmonic << ", " << a.harmonic_charts << " harmonic inside";
      if (a.untangled > 0) {
        harmonic << ", " << a.untangled << (a.untangled == 1 ? " vertex" : " vertices")
                 << " moved off turned faces";
      }
    } else {
      if (a.harmonic_charts > 0) {
        harmonic << "; " << a.harmonic_charts << " of the common subdivision drawn harmonic inside "
                 << "their border";
      }
      if (a.untangled > 0) {
        harmonic << "; " << a.untangled << (a.untangled == 1 ? " vertex" : " vertices")
                 << " of the common subdivision moved off turned faces";
      }
    }
    std::ostringstream packed;
    packed.precision(3);
    if (run.corners.empty()) {
      packed << "nothing to pack";
    } else if (context.packed_together) {
      packed << "packed with the other components";
    } else {
      packed << "packed: utilization " << a.utilization;
    }
    line("Atlas: ", cones.str(), "; ", a.num_charts, a.num_charts == 1 ? " chart (" : " charts (",
         a.splits, a.splits == 1 ? " split of an overlapping one" : " splits of overlapping ones",
         harmonic.str(), "), seams ", a.seam_length, " sqrt(area), ", a.overlapping_faces,
         " overlapping faces; ", packed.str());
    if (!p.bound_reached) line("Warning: the distortion bound was not reached: ", p.why_not);
    const std::string padding = padding_warning(a.padding, a.padding_asked);
    if (!padding.empty() && !context.packed_together) line(padding);
    const std::string tiny = below_a_texel_warning(a.charts_below_a_texel, a.num_charts, "charts");
    if (!tiny.empty() && !context.packed_together) line(tiny);
    // The linear model's D is a model's: the exact flat metric of its cones can exceed the bound.
    if (!a.user_cones && p.bound_reached && a.distortion > a.bound_asked) {
      line("Warning: the delivered faces' area distortion D ", a.distortion,
           " is above the bound asked, ", a.bound_asked, ", which the linear model's cones met (",
           p.distortion, ")");
    }
    if (a.unfolded == AtlasResult::Unfolded::NoAtlas) {
      line(
          "Warning: no placed cones gave an atlas, so the surface is unfolded, its own metric "
          "cut through every vertex of curvature: ",
          a.bound_instead);
    } else if (a.unfolded == AtlasResult::Unfolded::MoreConformal) {
      line(
          "The surface is unfolded, its own metric cut through every vertex of curvature, for a "
          "map nearer conformal: ",
          a.bound_instead);
    } else if (a.unfolded == AtlasResult::Unfolded::WithinBound) {
      line(
          "The surface is unfolded, its own metric cut through every vertex of curvature, for D "
          "within the bound: ",
          a.bound_instead);
    } else if (a.loops) {
      line(
          "Warning: the flow's edge flips made edges from a vertex to itself, which the flow "
          "without them wanted, and no other attempt gave an atlas: ",
          a.bound_instead);
    } else if (a.held_curvatures) {
      line("The cones keep u = 0 at them, not their curvatures of least D: ", a.bound_instead);
    } else if (!a.bound_instead.empty()) {
      line("The cones were placed again, for D <= ", a.bound, ": ", a.bound_instead);
    }
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

}  // namespace ricci
