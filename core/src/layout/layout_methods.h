// The two layout methods behind lay_out() and the gluing along the cut (not installed API).
#pragma once

#include <array>
#include <complex>
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

//! H2 charts grown as a development goes out (Layout::chart): a face of chart k whose new corner
//! would lie beyond chart_radius from k's centre goes into a chart of k whose centre is within
//! half of it, or a new one centred where the corner would go.
class ChartGrowth {
 public:
  //! Starts `layout`'s charts (chart_radius, chart_parent, chart_from_parent) with chart 0.
  ChartGrowth(Layout& layout, double chart_radius);
  //! The chart for a face of chart k whose new corner lies at z in k's coordinates: k, or a child
  //! of k (layout.chart_from_parent[result] moves k's coordinates into it).
  int chart_for(int k, std::complex<double> z);

 private:
  Layout& layout_;
  double rim_;                                // tanh(chart_radius / 2)
  std::vector<std::complex<double>> centre_;  // per chart, in its parent's coordinates
  std::vector<std::vector<int>> children_;
};

//! Fills the deck transformations (E2, H2), the closure error and the flipped-face count of a
//! layout whose corners and cut are set.
void glue_along_cut(const Triangulation& mesh, Layout& layout);

}  // namespace ricci::detail
