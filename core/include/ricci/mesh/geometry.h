// The three background geometries E2, H2, S2: the length law, the cosine law and their
// derivatives, written once here for all three. (The models they are laid out in, and the
// targets and normalizations that depend on the geometry, live in layout.h, presets.h and
// ricci_flow.h.)
//
// Edge length law (paper, Section 3, eqn. unified_circle_packing_edge_lengths), written with
// m = 2 eta e^(ui+uj) + eps_i e^(2ui) + eps_j e^(2uj) in a form free of cancellation:
//   E2:  l^2          = m
//   H2:  sinh^2(l/2)  = m / ((1 - eps_i e^(2ui)) (1 - eps_j e^(2uj)))
//   S2:  sin^2(l/2)   = m / ((1 + eps_i e^(2ui)) (1 + eps_j e^(2uj)))
// which is the paper's cosh l = ..., cos l = ... after subtracting 1 (see DESIGN.md, section 1).
#pragma once

#include <array>
#include <string>

namespace ricci {

inline constexpr double kPi = 3.14159265358979323846;

enum class Geometry { Euclidean, Hyperbolic, Spherical };

//! "euclidean", "hyperbolic", "spherical".
std::string to_string(Geometry g);
//! Inverse of to_string. \throws InvalidArgumentError for an unknown name.
Geometry geometry_from_string(const std::string& name);

//! Curvature kappa of the background: 0 (E2), -1 (H2), +1 (S2).
double background_curvature(Geometry g);

//! u = log r (E2), log tanh(r/2) (H2), log tan(r/2) (S2).
double conformal_factor_from_radius(Geometry g, double radius);

//! Inverse of conformal_factor_from_radius; NaN where no radius exists (H2 with u >= 0).
double radius_from_conformal_factor(Geometry g, double u);

//! Length of the edge ij and its partial derivatives in u_i and u_j.
struct EdgeLength {
  double length = 0;
  double d_ui = 0;
  double d_uj = 0;
  bool valid = false;  //!< false where the length law has no real positive solution
};

//! Length of edge ij from the conformal factors, scheme coefficients and conformal structure.
EdgeLength edge_length(Geometry g, double ui, double uj, int eps_i, int eps_j, double eta);
//! The same from xi = e^ui and xj = e^uj (a metric computes them once per vertex).
EdgeLength edge_length_of_exponentials(Geometry g, double xi, double xj, int eps_i, int eps_j,
                                       double eta);

//! The eta for which edge_length(g, ui, uj, eps_i, eps_j, eta).length == length.
double conformal_structure_from_length(Geometry g, double length, double ui, double uj, int eps_i,
                                       int eps_j);

//! Corner angles of one triangle and their derivatives in the edge lengths.
//! Lengths and angles are indexed by corner: l[k] is the edge opposite corner k.
struct TriangleAngles {
  std::array<double, 3> angle{};
  std::array<std::array<double, 3>, 3> d_angle_d_length{};  //!< [corner][edge]
  bool valid = false;  //!< false when the triangle inequality (or S2's perimeter < 2 pi) fails
};

//! True when the three lengths form a non-degenerate triangle of the geometry.
bool is_valid_triangle(Geometry g, const std::array<double, 3>& l);

//! Corner angles from the cosine law of the geometry, by the half-angle formula.
TriangleAngles corner_angles(Geometry g, const std::array<double, 3>& l);

//! Length of the side opposite the angle between sides x and y (the cosine law solved for the
//! third side). NaN when the result is not a valid length.
double third_side(Geometry g, double x, double y, double angle);

//! The apex (x, y), y >= 0, of the Euclidean triangle on the base from (0, 0) to (c, 0) whose
//! sides from the apex are b to (0, 0) and a to (c, 0). The angle at (0, 0) comes from the
//! half-angle law, which keeps a needle's small angle, and so its height, to its own precision
//! (the cosine law's height sqrt(b^2 - x^2) keeps only sqrt(eps) of b). Lengths that violate the
//! triangle inequality give the point of the base's line where the cosine law puts x (y = 0).
std::array<double, 2> triangle_apex(double c, double b, double a);

//! Area of a triangle with the given lengths and angles: Heron (E2), angle defect (H2),
//! angle excess (S2).
double triangle_area(Geometry g, const std::array<double, 3>& l,
                     const std::array<double, 3>& angle);

//! The quasi-conformal ratio of the affine map between two plane triangles given by their side
//! lengths (l[k] opposite corner k): the ratio of its singular values; infinity for a degenerate
//! triangle.
double quasi_conformal_ratio(const std::array<double, 3>& from, const std::array<double, 3>& to);

}  // namespace ricci
