// The two layout methods behind lay_out() and the gluing along the cut (not installed API).
#pragma once

#include <array>
#include <vector>

#include "layout/corners.h"
#include "ricci/layout/layout.h"

namespace ricci::detail {

//! The largest relative error in an edge's length that a developed plane layout may have before
//! plane_layout fits the edge vectors by least squares instead.
inline constexpr double kDevelopedLengthError = 1e-8;

//! E2, every topology: developed face by face, each wedge (a vertex's fan of faces on one side of
//! the cut) at the mean of its corners; where an edge's length is then off by more than
//! kDevelopedLengthError, least squares over the edge vectors with one unknown per wedge.
Layout plane_layout(const Triangulation& mesh, const std::vector<double>& lengths,
                    LinearSolverKind solver, double max_developed_error = kDevelopedLengthError);

//! Any geometry: triangle by triangle; H2 from a central face with a cut of shortest paths from it,
//! otherwise from the face deepest inside the cut disk. Sets the cut and the corners only: the
//! caller glues them (glue_along_cut) once its corners are final. H2 charts: of `chart_radius`.
Layout develop(const Triangulation& mesh, Geometry geometry, const std::vector<double>& lengths,
               double chart_radius = kChartRadius);

//! Fills the deck transformations and seam maps (E2, H2), the closure error and the flipped-face
//! count of a layout whose corners and cut are set.
void glue_along_cut(const Triangulation& mesh, Layout& layout);

//! Makes the two copies of a vertex inside a cut path images of each other under the layout's
//! seam_maps (the deck transformations, or in charts one per chart pair; welded copies): the
//! second copy, where within 1e-6 (hyperbolic distance; E2: of the layout's extent) of a seam
//! map's image (or its inverse's) of the first, is set to that image. Developed face by face, the
//! two sides of a cut differ by the drift of the development (the metric's rounding, amplified
//! in the hyperbolic plane with the distance travelled: openscad-tardis.stl 1e-12 in the disk's
//! coordinates, angle sums off by 1e-8 at cut vertices of small faces); glued by one isometry,
//! the faces around a cut vertex close up as around any other. Where paths meet (three copies
//! or more) the copies stay as developed: glued too, the seam maps' relation residual would land
//! there, and it is no smaller than the drift (occt-tr12j.stl: 1e-8 against 5e-9). Returns the
//! copies moved.
int glue_copies_across_cut(const std::vector<std::array<int, 3>>& faces, const Layout& layout,
                           std::vector<std::array<Eigen::Vector3d, 3>>& corners);

}  // namespace ricci::detail
