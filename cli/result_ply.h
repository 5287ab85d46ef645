// The PLY file ricci-flow writes: a contract that scripts, tests and MeshLab read.
//
// vertex: x y z, ricci_u ricci_radius ricci_curvature ricci_target (double; ricci_target is NaN
// where u was held fixed), and where a single-valued layout exists layout_x layout_y layout_z
// (double) plus, for planar layouts, texture_u texture_v (float). face: vertex_indices.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/compact_mesh.h"
#include "ricci/ricci_flow.h"

namespace ricci::cli {

struct ResultLayout {
  std::vector<Eigen::Vector3d> position;  //!< empty: no layout
  std::vector<Eigen::Vector2d> texture;   //!< empty: no texture coordinates
};

//! \throws IoError when the file cannot be written.
void write_result_ply(const std::string& path, const CompactMesh& mesh, const FlowResult& result,
                      const ResultLayout& layout, bool ascii);

}  // namespace ricci::cli
