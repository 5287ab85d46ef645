// One run of a request's preset (uniformize_once), how the runs not delivered add to the cost of
// the one that is, and the atlas's further attempts (atlas_attempts.cpp): its cones placed again
// for tighter bounds where the flow stalls or the layout fails, for the bound where the delivered
// faces' D exceeds it, for QC where a coarse part's faces are far from conformal, and the surface
// unfolded where that alone keeps to the request.
// Not installed API.
#pragma once

#include <string>

#include "ricci/flow/cone_placement.h"
#include "ricci/flow/ricci_flow.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/pipeline/uniformization.h"

namespace ricci::detail {

//! The run for the preset resolved from the request: the atlas's cones placed once (or
//! `unfolding`, unfolding_cones, where given), the flow, its layout (an atlas's not packed).
Uniformization uniformize_once(const CompactMesh& mesh, const UniformizationOptions& request,
                               const ConePlacement* unfolding = nullptr);

//! What an attempt that is not delivered adds to the cost (flows, iterations, factorizations,
//! times); its edge flips and convergence floor are not the delivered run's.
FlowTotals cost_of(const FlowTotals& attempt);
//! A cone placement's cost added to another's.
void add_placement_cost(ConePlacement& to, const ConePlacement& from);
//! What an attempt not delivered cost, its flows and its cone placement, added to these.
void add_cost(FlowTotals& totals, ConePlacement& placement, const Uniformization& attempt);
//! `instead`, delivered in place of `attempt`, whose cost counts before its own.
Uniformization delivered_instead(const Uniformization& attempt, Uniformization instead);
//! Why a run is not valid: "gave no map: ..." or "was not reached: ...".
std::string why_not_valid(const Uniformization& run);

//! uniformize (ricci/pipeline/uniformize.h) but for pack_atlas: for a component whose charts are
//! packed with those of the mesh's other components (uniformize_mesh).
Uniformization uniformize_unpacked(const CompactMesh& mesh, const UniformizationOptions& options);

//! uniformize_once, and for the atlas with placed cones: the cones of tighter bounds where it
//! gives no atlas, the surface unfolded where none does, and the cones placed again (at most
//! twice) where the delivered faces' D exceeds the bound, the lowest D delivered.
Uniformization uniformize_as_requested(const CompactMesh& mesh,
                                       const UniformizationOptions& request);

//! uniformize_as_requested, and for the atlas: the surface unfolded instead of the first atlas
//! that flowed where that atlas is far from conformal (QC p95 above 2) and the unfolding is more
//! conformal, through at most 64 cones or with seams within reach of the atlas's (through more
//! cones only where the budget is not the user's); else, weighed so against the atlas the retries
//! for D deliver, and unfolded where that atlas's D stays above the bound, or its QC p95 is above
//! 1.5 and the unfolding takes at most 64 cones with seams within reach; else, where QC p95 is
//! high, cones for tighter bounds delivered where they lower it enough (not at a budget the user
//! gave), and where it stays far from conformal, the unfolding where its seams stay within reach
//! of theirs.
Uniformization atlas_or_unfolded(const CompactMesh& mesh, const UniformizationOptions& request);

}  // namespace ricci::detail
