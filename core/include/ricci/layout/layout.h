// Layout of a metric of constant curvature in its model space: the plane (E2), the Poincare disk
// (H2), the unit sphere (S2).
//
// A surface that is not a disk (or a sphere) is first cut open into one (cut_graph.h), so a vertex
// on the cut has one position per fan of faces on each side of it: per face corner ("wedge")
// positions, glued across the cut by the deck transformations.
//   E2, every topology: developed triangle by triangle from the face deepest inside the cut disk,
//     each wedge at the mean of its corners. Where the round-off accumulated along the tree would
//     make an edge's length off by more than 1e-8 relative, edge directions are integrated across
//     the faces by the corner angles instead (errors add along a path, they do not multiply), and
//     positions are the sparse least-squares fit to every face's edge vectors, with separate
//     unknowns on the two sides of a cut (the method DESIGN.md measured as stable).
//   H2, S2: developed triangle by triangle, nearest to the seed first, each from the two corners
//     it shares with a placed face; H2 in long double, from a central face, cut along shortest
//     paths from it (so no corner lies far out in the Poincare disk, where double precision runs
//     out), S2 from the face deepest inside the cut disk.
#pragma once

#include <array>
#include <complex>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/layout/cut_graph.h"
#include "ricci/linear/linear_solver.h"
#include "ricci/mesh/geometry.h"
#include "ricci/mesh/triangulation.h"

namespace ricci {

//! An orientation-preserving isometry of the model: E2: z -> a z + b with |a| = 1; H2: the
//! Moebius map z -> (a z + b) / (conj(b) z + conj(a)) with |a|^2 - |b|^2 = 1 (of the disk).
struct DiskIsometry {
  Geometry geometry = Geometry::Euclidean;
  std::complex<double> a = 1, b = 0;

  std::complex<double> operator()(std::complex<double> z) const;
  DiskIsometry operator*(const DiskIsometry& other) const;  //!< (this o other)
  DiskIsometry inverse() const;
  //! The isometry that maps p0 to q0 and the direction of p1 from p0 to that of q1 from q0.
  static DiskIsometry mapping(Geometry g, std::complex<double> p0, std::complex<double> p1,
                              std::complex<double> q0, std::complex<double> q1);
  //! H2: z -> (z - p) / (1 - conj(p) z), which moves p to 0. \pre |p| < 1
  static DiskIsometry moving_to_origin(std::complex<double> p);
};

struct Layout {
  Geometry geometry = Geometry::Euclidean;
  //! Per face, per corner: E2 and H2 (Poincare disk) in x and y with z = 0; S2 unit vectors.
  std::vector<std::array<Eigen::Vector3d, 3>> corners;
  CutGraph cut;  //!< empty for a disk or a sphere
  //! E2 and H2, one per cut path: maps the path's positions on its right side (the face of the
  //! halfedge against the walk) to those on its left side.
  std::vector<DiskIsometry> deck;
  //! Largest distance (in the model's coordinates) between two positions of a vertex that should
  //! agree: across uncut edges, and across cut edges after the deck transformation.
  double closure_error = 0;
  //! surface_group_relation_error of the layout.
  double relation_error = 0;
  //! E2: max | |x_head - x_tail| / l - 1 | over the faces' edges.
  double max_relative_length_error = 0;
  int num_flipped_faces = 0;  //!< faces with non-positive orientation in the model
  //! H2 domains reaching farther from their centre than double precision draws in one Poincare
  //! disk (kOneChartRadius) are drawn in charts, each a piece of the domain moved by an isometry
  //! to lie within chart_radius of the disk's centre. Per face: its chart (empty: one chart, the
  //! domain itself). Chart k > 0 is chart_parent[k]'s coordinates moved by chart_from_parent[k];
  //! deck transformations are then not computed (deck empty, relation error NaN), and the closure
  //! error is over uncut edges, across charts by their transitions.
  std::vector<int> chart;
  std::vector<int> chart_parent;
  std::vector<DiskIsometry> chart_from_parent;
  double chart_radius = 0;  //!< when in charts
  //! Largest hyperbolic distance of a corner from the centre of the single-chart domain (H2; a
  //! lower bound beyond about 37, where |z| rounds to 1).
  double reach = 0;

  int num_charts() const { return chart.empty() ? 1 : static_cast<int>(chart_parent.size()); }
};

//! H2: a domain whose corners all lie within this hyperbolic distance of the disk's centre is
//! drawn in one chart (1 - |z| > 1.2e-5 there). Near the rim the disk's coordinates keep few
//! digits of a thin face: at distance 12 the corner angles of CGAL's elephant-with-holes were off
//! by up to 6e-6 in their sums, within distance 6 by 1e-10.
inline constexpr double kOneChartRadius = 12;
//! H2: the radius of each chart when the domain is drawn in several (1 - |z| > 2.5e-3), unless
//! the caller asks for smaller charts.
inline constexpr double kChartRadius = 6;

//! Per vertex: the position of the vertex in the first face (in face order) that holds it.
std::vector<Eigen::Vector3d> vertex_positions(const Triangulation& mesh, const Layout& layout);

//! The layout's corner positions for the faces of `other`, a triangulation of the same vertices
//! (the input, when the flow flipped edges): a face the layout has keeps its corners; for any
//! other face, its first vertex takes a position from a laid-out face and the others the wedge
//! position nearest to it.
std::vector<std::array<Eigen::Vector3d, 3>> corners_on(const Triangulation& laid_out,
                                                       const Layout& layout,
                                                       const Triangulation& other);

//! The surface group's relations, measured: walking once around an interior vertex where cut
//! paths meet, the deck transformations of the paths crossed compose to the identity (Poincare's
//! polygon theorem: these vertex cycles generate the relations, for a single-vertex cut
//! [a1, b1] ... [ag, bg] = 1). Returns the largest distance of such a product from the identity:
//! E2: max(|a - 1|, |b| / extent) with extent the layout's largest coordinate; H2:
//! max(|a -/+ 1|, |b|) relative to the largest |a| of the partial products (the entries the
//! composition went through, which rounding scales with: far-reaching domains compose isometries
//! with entries ~e^(distance / 2); rounding grows faster than that, so far-reaching domains still
//! show larger errors, and a relation broken by O(1) shows smaller); 0 for S2 and for cuts without
//! such vertices.
double surface_group_relation_error(const Triangulation& mesh, const Layout& layout);

//! S2: the Moebius transformation of the sphere that moves the points' centre of mass to the
//! origin (iterated ball automorphisms); returns the moved points. Only the first `count` points
//! make the centre of mass; all move. \pre unit vectors.
std::vector<Eigen::Vector3d> center_on_sphere(std::vector<Eigen::Vector3d> points,
                                              size_t count = static_cast<size_t>(-1));

//! Orientation of a laid-out triangle: positive when counter-clockwise in the plane or the disk,
//! or counter-clockwise seen from outside the sphere.
double orientation(Geometry geometry, const std::array<Eigen::Vector3d, 3>& corners);

//! The positions scaled and shifted into [0, 1]^2 with the aspect ratio kept: texture
//! coordinates.
std::vector<Eigen::Vector2d> normalized_texture_coordinates(
    const std::vector<Eigen::Vector2d>& position);

}  // namespace ricci
