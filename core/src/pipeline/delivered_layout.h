// The delivered layout of a converged flow: the layout of its result, the delivered mesh's
// positions and corners (the input's faces, or the common subdivision's where they would turn
// over), and what makes it no map (not installed API).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/target.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/pipeline/uniformization.h"

namespace ricci::detail {

//! The delivered mesh's positions and corners from the layout's (`position` per vertex of the
//! delivered mesh for per-vertex layouts, `corners` per input face otherwise): the sphere centred
//! where that turns no more faces over, the unit disk normalized.
void place_delivered(const CompactMesh& mesh, const UniformizationOptions& o, int outer_loop,
                     std::vector<Eigen::Vector3d> position,
                     std::vector<std::array<Eigen::Vector3d, 3>> corners, Uniformization& run);

//! Where the flow flipped edges and none of the input's faces turns over when drawn by its
//! `corners`: whether they are farther from conformal than `pieces`, the common subdivision (QC
//! p95 above 1.1 times the pieces', which add no collapsed face); then run.input_faces_qc_p95 is
//! set and the pieces are to be delivered.
bool pieces_more_conformal(const CompactMesh& mesh,
                           const std::vector<std::array<Eigen::Vector3d, 3>>& corners,
                           const CommonSubdivision& pieces, Uniformization& run);

//! Lays out run.result (H2 in charts of `chart_radius`) and fills run's layout kind, layout,
//! positions, corners, subdivision, face charts and torus periods; the unit disk normalized, the
//! sphere centred (where centring turns no more faces over than it leaves).
void lay_out_result(const CompactMesh& mesh, const UniformizationOptions& o, int outer_loop,
                    double chart_radius, Uniformization& run);

//! What makes a converged layout no map (faces turned over, the unit disk's loops off circles),
//! or "" for a valid one.
std::string layout_failure(const Uniformization& run);

}  // namespace ricci::detail
