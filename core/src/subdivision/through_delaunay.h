// The common subdivision of Yamabe (E2, S2) with isometric flips first: the input cut by its
// intrinsic Delaunay triangulation cut by the flow's final triangulation.
#pragma once

#include <cstddef>

#include "ricci/flow/flow_result.h"
#include "ricci/flow/scheme.h"
#include "ricci/layout/layout.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/subdivision/subdivided_mesh.h"

namespace ricci::detail {

// Ta cut by Tb cut by Tc; flips[0, split) are the isometric flips.
CommonSubdivision subdivision_through_delaunay(const CompactMesh& mesh,
                                               const ConformalStructure& initial,
                                               const FlowResult& result, const Layout& layout,
                                               size_t split, PieceTriangles how);

}  // namespace ricci::detail
