// The half's part of the common subdivision of a surface doubled along its boundary
// (doubled_surface.h), developed in the plane or the Poincare disk (not installed API).
#pragma once

#include <vector>

#include "ricci/layout/layout.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/subdivision/common_subdivision.h"

namespace ricci::detail {

struct HalfSubdivision {
  CommonSubdivision subdivision;  //!< of the half; corners and vertex_layout developed
  //! Plane: each piece's corners as developed, before the per-vertex mean that makes `corners`:
  //! isometric copies of the pieces, where the mean is not one around a cone (the atlas's).
  std::vector<std::array<Eigen::Vector3d, 3>> piece_corners;
  //! Plane: per edge of the half, its length in the final metric on the boundary, 0 inside;
  //! empty in the Poincare disk.
  std::vector<double> boundary_lengths;
  //! Plane: largest distance between a vertex's position and a piece's corner there; NaN in the
  //! Poincare disk (not measured).
  double closure_error = 0;
  //! Poincare disk: the reach, and where the pieces reach beyond kOneChartRadius the charts
  //! (chart per piece, chart_parent, chart_from_parent, chart_radius); no corners.
  Layout charts;
};

//! The pieces of the double's common subdivision that lie in the half's faces, renumbered (the
//! half's vertices first, then the new ones in the double's order), developed piece by piece,
//! each by its final face's isometry (across a final side, the one that puts the side's ends where
//! the neighbour's puts them): in the plane from the first piece, glued into one position per
//! vertex; in the Poincare disk from a central piece, with positions per corner (cut open where
//! the development did not cross), in charts beyond kOneChartRadius, new vertices on the geodesic
//! sides of their final faces. `twice` must be built on
//! `frames` (face_by_face_layout of `final_mesh`, the double's final triangulation).
//! \throws LayoutError when the pieces do not form one surface.
HalfSubdivision half_subdivision(const CompactMesh& half, const CommonSubdivision& twice,
                                 const Triangulation& final_mesh, const Layout& frames);

}  // namespace ricci::detail
