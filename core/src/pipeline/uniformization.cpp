#include "ricci/pipeline/uniformization.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ricci/flow/ricci_flow.h"
#include "ricci/mesh/errors.h"

namespace ricci {

void FlowTotals::add(const FlowResult& r) {
  FlowTotals one;
  if (r.flips_from_iteration >= 0) {
    one.flips_from_iteration = r.flips_from_iteration;
    one.without_flips = r.without_flips;
  }
  one.attainable_residual = r.attainable_residual;
  one.flows = 1;
  one.newton_iterations = r.iterations;
  one.edge_flips = r.num_flips;
  one.symbolic_analyses = r.num_analyses;
  one.numeric_factorizations = r.num_factorizations;
  one.krylov_iterations = r.krylov_iterations;
  one.times = r.times;
  add(one);
}

void FlowTotals::add(const FlowTotals& o) {
  attainable_residual = std::max(attainable_residual, o.attainable_residual);
  if (flips_from_iteration < 0 && o.flips_from_iteration >= 0) {
    flips_from_iteration = newton_iterations + o.flips_from_iteration;
    without_flips = o.without_flips;
  }
  flows += o.flows;
  newton_iterations += o.newton_iterations;
  edge_flips += o.edge_flips;
  symbolic_analyses += o.symbolic_analyses;
  numeric_factorizations += o.numeric_factorizations;
  krylov_iterations += o.krylov_iterations;
  for (auto [to, from] : {std::pair{&times.setup, o.times.setup},
                          {&times.assembly, o.times.assembly},
                          {&times.analysis, o.times.analysis},
                          {&times.factorization, o.times.factorization},
                          {&times.solve, o.times.solve},
                          {&times.line_search, o.times.line_search},
                          {&times.flips, o.times.flips},
                          {&times.total, o.times.total}}) {
    *to += from;
  }
}

void Uniformization::require_valid(const std::string& subject) const {
  if (!result.converged) {
    throw ConvergenceError(flow_failure_message(geometry, scheme, result, subject),
                           result.iterations, result.residual);
  }
  if (!layout_failure.empty()) {
    throw LayoutError("layout" + (subject.empty() ? "" : " of " + subject) + ": " + layout_failure);
  }
}

std::string to_string(AtlasResult::Unfolded u) {
  switch (u) {
    case AtlasResult::Unfolded::No:
      return "no";
    case AtlasResult::Unfolded::NoAtlas:
      return "no-atlas";
    case AtlasResult::Unfolded::MoreConformal:
      return "more-conformal";
    case AtlasResult::Unfolded::WithinBound:
      return "within-bound";
  }
  return "?";
}

std::string to_string(LayoutKind k) {
  switch (k) {
    case LayoutKind::None:
      return "none";
    case LayoutKind::Plane:
      return "plane";
    case LayoutKind::PlaneCut:
      return "plane-cut";
    case LayoutKind::PoincareDisk:
      return "poincare-disk";
    case LayoutKind::Sphere:
      return "sphere";
    case LayoutKind::Atlas:
      return "atlas";
  }
  return "?";
}

std::vector<std::array<Eigen::Vector2d, 3>> drawn_corners(const Uniformization& run) {
  std::vector<std::array<Eigen::Vector2d, 3>> drawn;
  if (run.layout_kind == LayoutKind::None || run.layout_kind == LayoutKind::Sphere) return drawn;
  if (run.layout_kind == LayoutKind::Atlas) return run.atlas.texture;
  const int charts = run.face_chart.empty() ? 1 : run.layout.num_charts();
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(charts))));
  for (size_t f = 0; f < run.corners.size(); ++f) {
    const int k = run.face_chart.empty() ? 0 : run.face_chart[f];
    const Eigen::Vector2d offset(2.25 * (k % columns), -2.25 * (k / columns));
    std::array<Eigen::Vector2d, 3> t;
    for (int c = 0; c < 3; ++c) t[c] = run.corners[f][c].head<2>() + offset;
    drawn.push_back(t);
  }
  return drawn;
}

TextureCoordinates texture_coordinates(const Uniformization& run) {
  TextureCoordinates t;
  if (run.layout_kind == LayoutKind::Plane) {
    std::vector<Eigen::Vector2d> planar;
    for (const auto& p : run.position) planar.emplace_back(p.x(), p.y());
    t.vertex = normalized_texture_coordinates(planar);
  } else if (run.layout_kind == LayoutKind::Atlas) {
    t.wedge = run.atlas.texture;
  } else if (run.layout_kind == LayoutKind::PlaneCut ||
             run.layout_kind == LayoutKind::PoincareDisk) {
    std::vector<Eigen::Vector2d> flat;
    for (const auto& face : drawn_corners(run)) {
      for (const auto& p : face) flat.push_back(p);
    }
    if (run.layout_kind == LayoutKind::PlaneCut || !run.face_chart.empty()) {
      flat = normalized_texture_coordinates(flat);
    } else {
      for (auto& p : flat) p = (p + Eigen::Vector2d::Ones()) / 2;
    }
    t.wedge.resize(run.corners.size());
    for (size_t f = 0; f < run.corners.size(); ++f) {
      for (int c = 0; c < 3; ++c) t.wedge[f][c] = flat[3 * f + c];
    }
  }
  return t;
}

LayoutKind planned_layout(const Triangulation& mesh, TargetPreset preset, Geometry geometry) {
  if (preset == TargetPreset::Atlas) return LayoutKind::Atlas;
  switch (geometry) {
    case Geometry::Euclidean:
      if (mesh.is_disk() || preset == TargetPreset::UnitDisk) return LayoutKind::Plane;
      return LayoutKind::PlaneCut;
    case Geometry::Hyperbolic:
      return LayoutKind::PoincareDisk;
    case Geometry::Spherical:
      return mesh.genus() == 0 ? LayoutKind::Sphere : LayoutKind::None;
  }
  return LayoutKind::None;
}

}  // namespace ricci
