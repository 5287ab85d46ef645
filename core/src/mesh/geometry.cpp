#include "ricci/mesh/geometry.h"

#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "mesh/plane.h"
#include "ricci/mesh/errors.h"

namespace ricci {

namespace {

// s(x) of the paper: x (E2), sinh x (H2), sin x (S2).
double s_of(Geometry g, double x) {
  switch (g) {
    case Geometry::Euclidean:
      return x;
    case Geometry::Hyperbolic:
      return std::sinh(x);
    case Geometry::Spherical:
      return std::sin(x);
  }
  return x;
}

// d log D / d u_i for the denominator factor (1 -+ eps_i e^(2ui)) of the length law.
double d_log_denominator(Geometry g, double a) {
  switch (g) {
    case Geometry::Euclidean:
      return 0;
    case Geometry::Hyperbolic:
      return -2 * a / (1 - a);
    case Geometry::Spherical:
      return 2 * a / (1 + a);
  }
  return 0;
}

double denominator_factor(Geometry g, double a) {
  switch (g) {
    case Geometry::Euclidean:
      return 1;
    case Geometry::Hyperbolic:
      return 1 - a;
    case Geometry::Spherical:
      return 1 + a;
  }
  return 1;
}

}  // namespace

std::string to_string(Geometry g) {
  switch (g) {
    case Geometry::Euclidean:
      return "euclidean";
    case Geometry::Hyperbolic:
      return "hyperbolic";
    case Geometry::Spherical:
      return "spherical";
  }
  return "unknown";
}

Geometry geometry_from_string(const std::string& name) {
  for (Geometry g : {Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical}) {
    if (to_string(g) == name) return g;
  }
  throw InvalidArgumentError("geometry: unknown geometry '" + name +
                             "'; use euclidean, hyperbolic or spherical");
}

double background_curvature(Geometry g) {
  switch (g) {
    case Geometry::Euclidean:
      return 0;
    case Geometry::Hyperbolic:
      return -1;
    case Geometry::Spherical:
      return 1;
  }
  return 0;
}

double conformal_factor_from_radius(Geometry g, double radius) {
  switch (g) {
    case Geometry::Euclidean:
      return std::log(radius);
    case Geometry::Hyperbolic:
      return std::log(std::tanh(radius / 2));
    case Geometry::Spherical:
      return std::log(std::tan(radius / 2));
  }
  return 0;
}

double radius_from_conformal_factor(Geometry g, double u) {
  const double e = std::exp(u);
  switch (g) {
    case Geometry::Euclidean:
      return e;
    case Geometry::Hyperbolic:
      return e < 1 ? 2 * std::atanh(e) : std::numeric_limits<double>::quiet_NaN();
    case Geometry::Spherical:
      return 2 * std::atan(e);
  }
  return e;
}

EdgeLength edge_length(Geometry g, double ui, double uj, int eps_i, int eps_j, double eta) {
  return edge_length_of_exponentials(g, std::exp(ui), std::exp(uj), eps_i, eps_j, eta);
}

EdgeLength edge_length_of_exponentials(Geometry g, double xi, double xj, int eps_i, int eps_j,
                                       double eta) {
  EdgeLength r;
  const double a = eps_i * xi * xi;
  const double b = eps_j * xj * xj;
  const double c = 2 * eta * xi * xj;
  const double m = c + a + b;  // m = 2 eta e^(ui+uj) + eps_i e^(2ui) + eps_j e^(2uj)
  const double di = denominator_factor(g, a);
  const double dj = denominator_factor(g, b);
  if (!(m > 0) || !(di > 0) || !(dj > 0)) return r;
  const double w = m / (di * dj);  // l^2, sinh^2(l/2) or sin^2(l/2)
  if (!std::isfinite(w)) return r;
  double half_tangent = 0;  // l/2, tanh(l/2), tan(l/2): dl/du = half_tangent * dlog(w)/du
  switch (g) {
    case Geometry::Euclidean:
      r.length = std::sqrt(w);
      half_tangent = r.length / 2;
      break;
    case Geometry::Hyperbolic:
      r.length = 2 * std::asinh(std::sqrt(w));
      half_tangent = std::sqrt(w / (1 + w));
      break;
    case Geometry::Spherical:
      if (!(w < 1)) return r;
      r.length = 2 * std::asin(std::sqrt(w));
      half_tangent = std::sqrt(w / (1 - w));
      break;
  }
  const double dlogw_i = (c + 2 * a) / m - d_log_denominator(g, a);
  const double dlogw_j = (c + 2 * b) / m - d_log_denominator(g, b);
  r.d_ui = half_tangent * dlogw_i;
  r.d_uj = half_tangent * dlogw_j;
  r.valid = r.length > 0 && std::isfinite(r.d_ui) && std::isfinite(r.d_uj);
  return r;
}

double conformal_structure_from_length(Geometry g, double length, double ui, double uj, int eps_i,
                                       int eps_j) {
  if (!(length > 0)) {
    throw InvalidArgumentError("conformal_structure_from_length: edge length must be positive");
  }
  const double a = eps_i * std::exp(2 * ui);
  const double b = eps_j * std::exp(2 * uj);
  double w = 0;
  switch (g) {
    case Geometry::Euclidean:
      w = length * length;
      break;
    case Geometry::Hyperbolic:
      w = std::pow(std::sinh(length / 2), 2);
      break;
    case Geometry::Spherical:
      w = std::pow(std::sin(length / 2), 2);
      break;
  }
  const double m = w * denominator_factor(g, a) * denominator_factor(g, b);
  return (m - a - b) / (2 * std::exp(ui + uj));
}

bool is_valid_triangle(Geometry g, const std::array<double, 3>& l) {
  const double s = (l[0] + l[1] + l[2]) / 2;
  for (double x : l) {
    if (!(x > 0) || !(s - x > 0)) return false;
  }
  if (g == Geometry::Spherical && !(s < kPi)) return false;
  return true;
}

TriangleAngles corner_angles(Geometry g, const std::array<double, 3>& l) {
  TriangleAngles t;
  if (!is_valid_triangle(g, l)) return t;
  const double s = (l[0] + l[1] + l[2]) / 2;
  // Half-angle law: tan^2(theta_i/2) = s(s-lj) s(s-lk) / (s(s) s(s-li)), with s() as above.
  const double ss = s_of(g, s);
  // Sine and cosine from the half angle's tangent h: sin = 2h / (1 + h^2), cos = (1 - h^2) /
  // (1 + h^2), without calls to sin and cos (their limits where h^2 would overflow).
  std::array<double, 3> sine, cosine;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const double num = s_of(g, s - l[j]) * s_of(g, s - l[k]);
    const double den = ss * s_of(g, s - l[i]);
    const double h = std::sqrt(num / den);
    t.angle[i] = 2 * std::atan(h);
    if (h < 1e150) {
      const double q = 1 / (1 + h * h);
      sine[i] = 2 * h * q;
      cosine[i] = (1 - h * h) * q;
    } else {  // the angle is pi to within rounding
      sine[i] = 2 / h;
      cosine[i] = -1;
    }
  }
  // d theta_i / d l_i = s(l_i)/A, d theta_i / d l_j = -s(l_i) cos(theta_k)/A with
  // A = sin(theta_i) s(l_j) s(l_k), symmetric in i, j, k by the sine law.
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const double area_term = sine[i] * s_of(g, l[j]) * s_of(g, l[k]);
    const double di = s_of(g, l[i]) / area_term;
    t.d_angle_d_length[i][i] = di;
    t.d_angle_d_length[i][j] = -di * cosine[k];
    t.d_angle_d_length[i][k] = -di * cosine[j];
  }
  t.valid = true;
  for (int i = 0; i < 3; ++i) {
    for (int e = 0; e < 3; ++e) t.valid = t.valid && std::isfinite(t.d_angle_d_length[i][e]);
  }
  return t;
}

double third_side(Geometry g, double x, double y, double angle) {
  // The cosine law written without cancellation, with h = sin^2(angle / 2):
  //   E2: (c/2)^2 = ((x-y)/2)^2 + x y h;  H2: sinh^2(c/2) = sinh^2((x-y)/2) + sinh x sinh y h;
  //   S2: sin^2(c/2) = sin^2((x-y)/2) + sin x sin y h.
  const double h = std::pow(std::sin(angle / 2), 2);
  switch (g) {
    case Geometry::Euclidean:
      return 2 * std::sqrt(std::pow((x - y) / 2, 2) + x * y * h);
    case Geometry::Hyperbolic:
      return 2 * std::asinh(std::sqrt(std::pow(std::sinh((x - y) / 2), 2) +
                                      std::sinh(x) * std::sinh(y) * h));
    case Geometry::Spherical:
      return 2 * std::asin(
                     std::sqrt(std::pow(std::sin((x - y) / 2), 2) + std::sin(x) * std::sin(y) * h));
  }
  return std::numeric_limits<double>::quiet_NaN();
}

std::array<double, 2> triangle_apex(double c, double b, double a) {
  const double sa = (b + c - a) / 2, sb = (a + c - b) / 2, sc = (a + b - c) / 2;
  if (!(sa > 0 && sb > 0 && sc > 0)) return {(b * b + c * c - a * a) / (2 * c), 0.0};
  const double h2 = sb * sc / ((sa + sb + sc) * sa);  // tan^2 of half the angle at (0, 0)
  return {b * (1 - h2) / (1 + h2), b * 2 * std::sqrt(h2) / (1 + h2)};
}

double triangle_area(Geometry g, const std::array<double, 3>& l,
                     const std::array<double, 3>& angle) {
  switch (g) {
    case Geometry::Euclidean:
      return 0.5 * l[1] * l[2] * std::sin(angle[0]);
    case Geometry::Hyperbolic:
      return kPi - angle[0] - angle[1] - angle[2];
    case Geometry::Spherical:
      return angle[0] + angle[1] + angle[2] - kPi;
  }
  return 0;
}

namespace {

// Corners 1 and 2 of a plane triangle with corner 0 at the origin and corner 1 on the +x axis.
Eigen::Matrix2d triangle_frame(const std::array<double, 3>& l) {
  const double c = l[1], b = l[2];               // |01| = l[2], |02| = l[1]
  if (!(b > 0)) return Eigen::Matrix2d::Zero();  // collapsed
  const auto [x, y] = triangle_apex(b, c, l[0]);
  Eigen::Matrix2d m;
  m << b, x, 0, y;
  return m;
}

}  // namespace

double quasi_conformal_ratio(const std::array<double, 3>& from, const std::array<double, 3>& to) {
  const Eigen::Matrix2d p = triangle_frame(from), q = triangle_frame(to);
  if (!(std::abs(p.determinant()) > 0) || !(std::abs(q.determinant()) > 0)) {
    return std::numeric_limits<double>::infinity();
  }
  return detail::singular_value_ratio(q * p.inverse(), q.determinant() / p.determinant());
}

}  // namespace ricci
