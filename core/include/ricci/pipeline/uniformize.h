// Uniformization: a target preset, the flow, and the layout of the result in its model space,
// measured. The one pipeline behind `ricci-flow` and the MeshLab filter:
//
//   resolve_request     preset and geometry (presets.h: one rule by topology), checked
//   the flow            one solve; the disk preset repeats it until every boundary loop is a
//                       circle (circle_domain.h)
//   the layout          layout.h, then per-vertex positions where the layout has them; the
//                       unit disk normalized (centre and axis vertex), the sphere centred
//   the quality         layout_quality.h, against the input mesh
//
//   disk (E2)              one position per vertex in the plane; with the disk preset on the unit
//                          circle, optionally Moebius-normalized (center and axis vertex)
//   circle domain (E2)     genus 0 with several boundary loops, disk preset: the cut closes up
//                          (deck transformations ~ identity), outer loop the unit circle
//   cut open (E2, H2)      torus, higher genus, other targets: per-corner (wedge) positions in
//                          the plane or the Poincare disk, deck transformations, closure error
//   sphere (S2)            genus 0: vertices on the unit sphere, centre of mass at the origin
#pragma once

#include <utility>

#include "ricci/flow/target.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/mesh/geometry.h"
#include "ricci/pipeline/uniformization.h"

namespace ricci {

//! The preset (never Automatic) and geometry a request resolves to, checked.
//! \throws InvalidTargetError, InvalidArgumentError naming what cannot be done and why.
std::pair<TargetPreset, Geometry> resolve_request(const CompactMesh& mesh,
                                                  const UniformizationOptions& options);

//! Runs the preset's flow and lays out its result. Never throws for non-convergence or an invalid
//! layout: the result says why (require_valid() turns that into an error). The automatic target
//! without cones, centre or axis is best effort: where the circle domain gives no map, the free
//! boundary (target_instead); where the Yamabe scheme gives none for the topology's target (for a
//! circle domain, with neither), the tangential scheme (scheme_instead; not with EdgeFlips::Never
//! or keep_input_triangulation); each only where it is valid, else the failure says it was tried.
//! An atlas's charts are packed into [0, 1]^2 (options.packing) for the attempt delivered:
//! AtlasResult::texture, utilization, padding (uniformize_mesh packs the charts of a mesh of
//! several components together instead).
//! \throws InvalidTargetError, InvalidArgumentError for requests that admit no solution (named).
Uniformization uniformize(const CompactMesh& mesh, const UniformizationOptions& options);

}  // namespace ricci
