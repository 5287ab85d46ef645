#include "ricci/flow/target.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "ricci/mesh/errors.h"

namespace ricci {

namespace {

double prescribed_sum(const TargetCurvature& target) {
  double sum = 0;
  for (int v = 0; v < target.curvature.size(); ++v) {
    if (!target.is_fixed(v)) sum += target.curvature[v];
  }
  return sum;
}
}  // namespace

int TargetCurvature::num_fixed() const {
  int n = 0;
  for (char f : fixed) n += f != 0;
  return n;
}

Eigen::VectorXd TargetCurvature::values() const {
  Eigen::VectorXd v = curvature;
  for (int i = 0; i < v.size(); ++i) {
    if (is_fixed(i)) v[i] = std::numeric_limits<double>::quiet_NaN();
  }
  return v;
}

TargetCurvature TargetCurvature::zero(const CompactMesh& mesh) {
  TargetCurvature t;
  t.curvature = Eigen::VectorXd::Zero(mesh.num_vertices());
  t.fixed.assign(mesh.num_vertices(), 0);
  return t;
}

TargetCurvature TargetCurvature::free_boundary(const CompactMesh& mesh) {
  TargetCurvature t = zero(mesh);
  for (int v = 0; v < mesh.num_vertices(); ++v) t.fixed[v] = mesh.is_boundary_vertex(v);
  return t;
}

TargetCurvature TargetCurvature::from_values(const CompactMesh& mesh,
                                             const Eigen::VectorXd& values) {
  if (values.size() != mesh.num_vertices()) {
    throw InvalidTargetError("target curvature: " + std::to_string(values.size()) +
                             " values for a mesh of " + std::to_string(mesh.num_vertices()) +
                             " vertices; give one value per vertex, in vertex order");
  }
  TargetCurvature t = zero(mesh);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (std::isnan(values[v])) {
      t.fixed[v] = 1;
    } else {
      t.curvature[v] = values[v];
    }
  }
  return t;
}

TargetCurvature TargetCurvature::free_boundary_or_zero(const CompactMesh& mesh) {
  return mesh.is_closed() ? zero(mesh) : free_boundary(mesh);
}

void check_target(const CompactMesh& mesh, Geometry geometry, const TargetCurvature& target) {
  const int n = mesh.num_vertices();
  if (target.curvature.size() != n || static_cast<int>(target.fixed.size()) != n) {
    throw InvalidTargetError("target curvature: sized for " +
                             std::to_string(target.curvature.size()) + " vertices, the mesh has " +
                             std::to_string(n));
  }
  for (int v = 0; v < n; ++v) {
    if (target.is_fixed(v)) continue;
    const double k = target.curvature[v];
    const double limit = mesh.is_boundary_vertex(v) ? kPi : 2 * kPi;
    if (!std::isfinite(k) || k >= limit) {
      std::ostringstream s;
      s << "target curvature: vertex " << v << " asks for Kbar = " << k << ", but a "
        << (mesh.is_boundary_vertex(v) ? "boundary vertex needs Kbar < pi"
                                       : "vertex needs Kbar < 2 pi")
        << " (its angle sum must stay positive); lower it";
      throw InvalidTargetError(s.str());
    }
  }
  if (target.num_fixed() > 0) return;  // the fixed vertices absorb the Gauss-Bonnet balance

  const double two_pi_chi = 2 * kPi * mesh.euler_characteristic();
  const double sum = prescribed_sum(target);
  const double scale = std::max(1.0, std::abs(two_pi_chi)) + std::abs(sum);
  const double slack = 1e-9 * scale;
  std::ostringstream s;
  s.precision(10);
  const std::string topo =
      mesh.topology_name() + " (chi = " + std::to_string(mesh.euler_characteristic()) + ")";
  switch (geometry) {
    case Geometry::Euclidean:
      if (std::abs(sum - two_pi_chi) > slack) {
        s << "target curvature: Gauss-Bonnet fails in euclidean geometry: sum Kbar = " << sum
          << " but 2 pi chi = " << two_pi_chi << " on this " << topo << "; ";
        if (mesh.is_closed() && mesh.genus() == 0) {
          s << "a closed genus-0 surface is flat only with cones: use spherical geometry, or "
               "prescribe cone curvatures summing to 4 pi";
        } else if (mesh.is_closed() && mesh.genus() >= 2) {
          s << "use hyperbolic geometry for Kbar = 0, or prescribe curvatures summing to 2 pi chi";
        } else {
          s << "make the values sum to 2 pi chi, or fix u on the boundary (free-boundary target)";
        }
        throw InvalidTargetError(s.str());
      }
      break;
    case Geometry::Hyperbolic:
      // sum K - A = 2 pi chi: the area A = sum Kbar - 2 pi chi must be positive.
      if (!(sum - two_pi_chi > slack)) {
        s << "target curvature: hyperbolic geometry needs sum Kbar > 2 pi chi (the area "
          << "sum Kbar - 2 pi chi must be positive), but sum Kbar = " << sum
          << " and 2 pi chi = " << two_pi_chi << " on this " << topo << "; ";
        s << (mesh.is_closed() && mesh.genus() <= 1
                  ? "a closed surface of genus 0 or 1 carries no hyperbolic metric with Kbar = 0: "
                    "use spherical (genus 0) or euclidean (genus 1) geometry"
                  : "raise the target curvatures or fix u on the boundary");
        throw InvalidTargetError(s.str());
      }
      break;
    case Geometry::Spherical:
      // sum K + A = 2 pi chi: the area A = 2 pi chi - sum Kbar must be positive.
      if (!(two_pi_chi - sum > slack)) {
        s << "target curvature: spherical geometry needs sum Kbar < 2 pi chi (the area "
          << "2 pi chi - sum Kbar must be positive), but sum Kbar = " << sum
          << " and 2 pi chi = " << two_pi_chi << " on this " << topo << "; ";
        s << (mesh.is_closed() && mesh.genus() >= 1
                  ? "a closed surface of genus >= 1 carries no spherical metric with Kbar = 0: "
                    "use euclidean (genus 1) or hyperbolic (genus >= 2) geometry"
                  : "lower the target curvatures or fix u on the boundary");
        throw InvalidTargetError(s.str());
      }
      break;
  }
}

double gauss_bonnet_area(const CompactMesh& mesh, Geometry geometry,
                         const TargetCurvature& target) {
  if (geometry == Geometry::Euclidean || target.num_fixed() > 0) return 0;
  return std::abs(2 * kPi * mesh.euler_characteristic() - prescribed_sum(target));
}

}  // namespace ricci
