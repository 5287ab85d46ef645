#include "ricci/uniformize.h"

#include <cmath>
#include <complex>
#include <sstream>

#include <Eigen/Dense>

#include "ricci/errors.h"
#include "spherical_start.h"

namespace ricci {

namespace {

// The circle through the points (algebraic least squares): centre and radius.
std::pair<Eigen::Vector2d, double> fit_circle(const std::vector<Eigen::Vector3d>& points,
                                              const std::vector<int>& which) {
  Eigen::MatrixXd a(which.size(), 3);
  Eigen::VectorXd b(which.size());
  for (size_t i = 0; i < which.size(); ++i) {
    const Eigen::Vector3d& p = points[which[i]];
    a.row(static_cast<long>(i)) << p.x(), p.y(), 1.0;
    b[static_cast<long>(i)] = -(p.x() * p.x() + p.y() * p.y());
  }
  const Eigen::Vector3d d = a.colPivHouseholderQr().solve(b);
  const Eigen::Vector2d center(-d[0] / 2, -d[1] / 2);
  return {center, std::sqrt(std::max(0.0, center.squaredNorm() - d[2]))};
}

double circle_error(const std::vector<Eigen::Vector3d>& points, const Triangulation& mesh) {
  double error = 0;
  for (const auto& loop : mesh.boundary_loops()) {
    const auto [center, radius] = fit_circle(points, loop);
    for (int v : loop) {
      error = std::max(error, std::abs((points[v].head<2>() - center).norm() - radius) / radius);
    }
  }
  return error;
}

std::vector<std::array<Eigen::Vector3d, 3>> corners_of(const Triangulation& mesh,
                                                       const std::vector<Eigen::Vector3d>& x) {
  std::vector<std::array<Eigen::Vector3d, 3>> corners(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) corners[f][c] = x[mesh.face_vertex(f, c)];
  }
  return corners;
}

Geometry preset_geometry(const CompactMesh& mesh, TargetPreset preset) {
  switch (preset) {
    case TargetPreset::UnitDisk:
    case TargetPreset::FreeBoundary:
      return Geometry::Euclidean;
    case TargetPreset::Zero:
      if (mesh.is_closed()) return automatic_geometry(mesh);
      return mesh.euler_characteristic() < 0 ? Geometry::Hyperbolic : Geometry::Euclidean;
    default:
      return automatic_preset(mesh).second;
  }
}

void check_request(const CompactMesh& mesh, TargetPreset preset, Geometry geometry,
                   const UniformizationOptions& o) {
  const std::string topology = mesh.topology_name();
  if (preset == TargetPreset::UnitDisk) {
    if (mesh.is_closed() || mesh.genus() != 0) {
      throw InvalidTargetError(
          "the disk target maps a genus-0 surface with boundary to the unit "
          "disk, but the mesh is a " +
          topology + "; use the auto target (it picks the metric for this topology)");
    }
    if (geometry != Geometry::Euclidean) {
      throw InvalidTargetError(
          "the disk target is a euclidean layout; choose euclidean (or "
          "auto) geometry instead of " +
          to_string(geometry));
    }
  }
  if (preset == TargetPreset::FreeBoundary && mesh.is_closed()) {
    throw InvalidTargetError("the free-boundary target needs a boundary, but the mesh is a " +
                             topology + "; use the zero or auto target");
  }
  for (const auto& [vertex, name] :
       {std::pair{o.center_vertex, "center"}, std::pair{o.axis_vertex, "axis"}}) {
    if (vertex < 0) continue;
    if (preset != TargetPreset::UnitDisk) {
      throw InvalidArgumentError(std::string("the ") + name +
                                 " vertex normalizes the unit disk map; it needs the disk target");
    }
    if (vertex >= mesh.num_vertices()) {
      throw InvalidArgumentError(std::string("the ") + name + " vertex " + std::to_string(vertex) +
                                 " is out of range: the mesh has vertices "
                                 "0.." +
                                 std::to_string(mesh.num_vertices() - 1));
    }
  }
  if (o.center_vertex >= 0 && mesh.is_boundary_vertex(o.center_vertex)) {
    throw InvalidArgumentError("the center vertex " + std::to_string(o.center_vertex) +
                               " lies on the boundary, which maps to the unit circle; choose an "
                               "interior vertex");
  }
  if (o.center_vertex >= 0 && o.center_vertex == o.axis_vertex) {
    throw InvalidArgumentError("the axis vertex must differ from the center vertex");
  }
}

// Anderson acceleration of the fixed-point iteration x -> g(x) on the boundary curvature: the
// next x is the combination of the last few g values whose residuals g - x cancel best.
class AndersonMixing {
 public:
  explicit AndersonMixing(int depth) : depth_(depth) {}

  Eigen::VectorXd next(const Eigen::VectorXd& x, const Eigen::VectorXd& g) {
    const Eigen::VectorXd f = g - x;
    if (has_last_) {
      df_.push_back(f - last_f_);
      dg_.push_back(g - last_g_);
      if (static_cast<int>(df_.size()) > depth_) df_.erase(df_.begin()), dg_.erase(dg_.begin());
    }
    last_f_ = f, last_g_ = g, has_last_ = true;
    if (df_.empty()) return g;
    Eigen::MatrixXd a(f.size(), static_cast<long>(df_.size()));
    for (size_t k = 0; k < df_.size(); ++k) a.col(static_cast<long>(k)) = df_[k];
    const Eigen::VectorXd gamma = a.colPivHouseholderQr().solve(f);
    Eigen::VectorXd result = g;
    for (size_t k = 0; k < dg_.size(); ++k) result -= gamma[static_cast<long>(k)] * dg_[k];
    return result;
  }
  void reset() { df_.clear(), dg_.clear(), has_last_ = false; }

 private:
  int depth_;
  std::vector<Eigen::VectorXd> df_, dg_;
  Eigen::VectorXd last_f_, last_g_;
  bool has_last_ = false;
};

}  // namespace

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
  }
  return "?";
}

TextureCoordinates texture_coordinates(const Uniformization& u) {
  TextureCoordinates t;
  if (u.layout == LayoutKind::Plane) {
    std::vector<Eigen::Vector2d> planar;
    for (const auto& p : u.position) planar.emplace_back(p.x(), p.y());
    t.vertex = normalized_texture_coordinates(planar);
  } else if (u.layout == LayoutKind::PlaneCut || u.layout == LayoutKind::PoincareDisk) {
    std::vector<Eigen::Vector2d> flat;
    for (const auto& face : u.corners) {
      for (const auto& p : face) flat.push_back(p.head<2>());
    }
    if (u.layout == LayoutKind::PlaneCut) {
      flat = normalized_texture_coordinates(flat);
    } else {
      for (auto& p : flat) p = (p + Eigen::Vector2d::Ones()) / 2;
    }
    t.wedge.resize(u.corners.size());
    for (size_t f = 0; f < u.corners.size(); ++f) {
      for (int c = 0; c < 3; ++c) t.wedge[f][c] = flat[3 * f + c];
    }
  }
  return t;
}

std::vector<Eigen::Vector3d> normalize_to_unit_disk(std::vector<Eigen::Vector3d> points,
                                                    const std::vector<int>& boundary, int center,
                                                    int axis) {
  using Complex = std::complex<double>;
  const auto [c, r] = fit_circle(points, boundary);
  for (auto& p : points) p = Eigen::Vector3d((p.x() - c.x()) / r, (p.y() - c.y()) / r, 0.0);
  if (center >= 0) {
    const Complex a(points[center].x(), points[center].y());
    if (!(std::abs(a) < 1 - 1e-12)) {
      throw InvalidArgumentError("the center vertex " + std::to_string(center) +
                                 " is on the unit circle; choose an interior vertex");
    }
    for (auto& p : points) {
      const Complex z(p.x(), p.y());
      const Complex w = (z - a) / (1.0 - std::conj(a) * z);
      p = Eigen::Vector3d(w.real(), w.imag(), 0.0);
    }
  }
  if (axis >= 0) {
    const Complex z(points[axis].x(), points[axis].y());
    if (!(std::abs(z) > 1e-12)) {
      throw InvalidArgumentError("the axis vertex " + std::to_string(axis) +
                                 " maps to the centre, so it fixes no direction; choose another");
    }
    const Complex turn = std::conj(z) / std::abs(z);
    for (auto& p : points) {
      const Complex w = turn * Complex(p.x(), p.y());
      p = Eigen::Vector3d(w.real(), w.imag(), 0.0);
    }
  }
  return points;
}

std::pair<TargetPreset, Geometry> resolve_request(const CompactMesh& mesh,
                                                  const UniformizationOptions& o) {
  TargetPreset preset = o.preset;
  Geometry geometry;
  if (preset == TargetPreset::Automatic) {
    const auto automatic = automatic_preset(mesh);
    preset = automatic.first;
    geometry = o.geometry.value_or(automatic.second);
  } else if (preset == TargetPreset::Values) {
    geometry = o.geometry.value_or(
        geometry_for_target(mesh, TargetCurvature::from_values(mesh, o.values)));
  } else {
    geometry = o.geometry.value_or(preset_geometry(mesh, preset));
  }
  check_request(mesh, preset, geometry, o);
  return {preset, geometry};
}

LayoutKind planned_layout(const Triangulation& mesh, TargetPreset preset, Geometry geometry) {
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

Uniformization uniformize(const CompactMesh& mesh, const UniformizationOptions& o) {
  Uniformization out;
  const auto [preset, geometry] = resolve_request(mesh, o);
  TargetCurvature target;
  if (preset == TargetPreset::Values) target = TargetCurvature::from_values(mesh, o.values);
  out.preset = preset;
  out.geometry = geometry;

  int outer = -1;
  switch (preset) {
    case TargetPreset::UnitDisk:
      outer = outer_boundary_loop(mesh, mesh.input_lengths());
      target = circle_boundary_target(mesh, mesh.input_lengths(), outer);
      break;
    case TargetPreset::FreeBoundary:
      target = TargetCurvature::free_boundary(mesh);
      break;
    case TargetPreset::Zero:
      target = TargetCurvature::zero(mesh);
      break;
    default:
      break;
  }
  out.structure = prepare_flow(mesh, geometry, o.scheme, target);

  // --- the flow; for the disk preset repeated, the boundary curvature re-fitted each time
  // The boundary curvature is a fixed point of flow -> circle_boundary_target, found by
  // Anderson-accelerated iteration; a combination the flow cannot reach falls back to the plain
  // iteration. Each flow starts where the previous one ended (the solver keeps u, the flipped
  // triangulation and the symbolic analysis).
  RicciFlowSolver solver(mesh, out.structure, o.flow);
  const std::optional<Eigen::VectorXd> start = flow_start(mesh, out.structure, target, o.flow);
  AndersonMixing mixing(5);
  TargetCurvature plain = target;  // the last plain iterate, g(x)
  bool warm = false;               // this flow starts from the last converged one
  for (;;) {
    out.result = solver.solve(target, start ? &*start : nullptr);
    out.newton_iterations += out.result.iterations;
    if (preset != TargetPreset::UnitDisk) break;
    ++out.boundary_iterations;
    if (!out.result.converged) {
      // Retry once with the plain iterate from a cold start; give up when that failed.
      if (target.curvature == plain.curvature && !warm) break;
      mixing.reset();
      target = plain;
      solver.restart();
      warm = false;
      continue;
    }
    const TargetCurvature next = circle_boundary_target(result_triangulation(mesh, out.result),
                                                        out.result.edge_lengths, outer);
    out.boundary_change = (next.curvature - target.curvature).cwiseAbs().maxCoeff();
    if (out.boundary_change <= o.boundary_tolerance) break;
    if (out.boundary_iterations >= o.max_boundary_iterations) {
      std::ostringstream s;
      s << "the boundary curvature still changed by " << out.boundary_change << " after "
        << out.boundary_iterations << " flows (tolerance " << o.boundary_tolerance
        << "); raise the boundary iteration limit";
      out.result.converged = false;
      out.result.failure = s.str();
      break;
    }
    plain = next;
    warm = true;
    target.curvature = mixing.next(target.curvature, next.curvature);
    try {
      check_target(mesh, geometry, target);
    } catch (const InvalidTargetError&) {
      mixing.reset();
      target = plain;
    }
  }
  if (!out.result.converged) {
    out.quality = measure_layout(mesh, geometry, out.result, {});
    return out;
  }

  // --- the layout
  const Triangulation& flowed = result_triangulation(mesh, out.result);
  const std::vector<double>& lengths = out.result.edge_lengths;
  out.layout = planned_layout(mesh, preset, geometry);
  if (geometry == Geometry::Euclidean && mesh.is_disk()) {
    const PlanarLayout planar = layout_disk(flowed, lengths, o.flow.linear_solver);
    out.max_relative_length_error = planar.max_relative_length_error;
    for (const auto& p : planar.position) out.position.emplace_back(p.x(), p.y(), 0.0);
  } else {
    out.model = develop(flowed, geometry, lengths);
    out.relation_error = surface_group_relation_error(flowed, *out.model);
    switch (out.layout) {
      case LayoutKind::Sphere:
        out.position = vertex_positions(flowed, *out.model);
        if (mesh.is_closed()) out.position = center_on_sphere(std::move(out.position));
        break;
      case LayoutKind::Plane:  // a circle domain: the cut closes up
        out.position = vertex_positions(flowed, *out.model);
        break;
      case LayoutKind::PlaneCut:
      case LayoutKind::PoincareDisk:
        out.corners = corners_on(flowed, *out.model, mesh);
        break;
      case LayoutKind::None:
        break;
    }
  }
  if (preset == TargetPreset::UnitDisk) {
    out.position = normalize_to_unit_disk(std::move(out.position), mesh.boundary_loops()[outer],
                                          o.center_vertex, o.axis_vertex);
    out.circle_error = circle_error(out.position, mesh);
  }
  if (out.model && geometry == Geometry::Euclidean && mesh.is_closed() && mesh.genus() == 1) {
    // The deck translations are sums of two generators; the most independent pair spans them.
    double best = 0;
    for (const DiskIsometry& a : out.model->deck) {
      for (const DiskIsometry& b : out.model->deck) {
        const double cross = std::abs(std::imag(std::conj(a.b) * b.b));
        if (cross > best) best = cross, out.periods = {a.b, b.b};
      }
    }
  }
  if (!out.position.empty()) out.corners = corners_of(mesh, out.position);
  out.quality = measure_layout(mesh, geometry, out.result, out.corners);
  return out;
}

}  // namespace ricci
