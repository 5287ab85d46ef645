#include "ricci/layout/lay_out.h"

#include <algorithm>
#include <cmath>

#include "layout/layout_methods.h"
#include "ricci/mesh/errors.h"

namespace ricci {

Layout lay_out(const Triangulation& mesh, Geometry geometry, const std::vector<double>& lengths,
               LinearSolverKind solver, double chart_radius) {
  // Its wedges, deck transformations and relation walk find corners by their vertex.
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (mesh.edge_vertices(e)[0] == mesh.edge_vertices(e)[1]) {
      throw LayoutError("the flowed triangulation has an edge from a vertex to itself (" +
                        std::to_string(e) + "), which this layout does not follow");
    }
  }
  Layout layout;
  if (geometry == Geometry::Euclidean) {
    layout = detail::plane_layout(mesh, lengths, solver);
  } else {
    layout = detail::develop(mesh, geometry, lengths, std::min(chart_radius, kChartRadius));
    detail::glue_along_cut(mesh, layout);
  }
  layout.relation_error =
      layout.chart.empty() ? surface_group_relation_error(mesh, layout) : std::nan("");
  return layout;
}

}  // namespace ricci
