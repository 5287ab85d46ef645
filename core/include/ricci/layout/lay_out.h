// lay_out: a metric's layout in its model space by the method for its geometry (layout.h describes
// the methods and what a Layout holds).
#pragma once

#include <vector>

#include "ricci/layout/layout.h"
#include "ricci/linear/linear_solver.h"
#include "ricci/mesh/geometry.h"
#include "ricci/mesh/triangulation.h"

namespace ricci {

//! Lays out `lengths`, a metric of the geometry with angle sum 2 pi at interior vertices (a
//! converged flow's), by the method for its geometry (see the top of this file).
//! \throws InvalidArgumentError for lengths that are not a valid metric of the geometry;
//!   LayoutError for a triangulation with an edge from a vertex to itself (FlowOptions::loops).
//! H2 domains in charts: each within `chart_radius` (at most kChartRadius) of its disk's centre.
Layout lay_out(const Triangulation& mesh, Geometry geometry, const std::vector<double>& lengths,
               LinearSolverKind solver = LinearSolverKind::Cholmod,
               double chart_radius = kChartRadius);

}  // namespace ricci
