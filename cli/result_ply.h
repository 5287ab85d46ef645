// The PLY file ricci-flow writes: a contract that scripts, tests and MeshLab read.
//
// vertex: x y z, ricci_u ricci_radius ricci_curvature ricci_target (double; ricci_target is NaN
// where u was held fixed), and where a single-valued layout exists layout_x layout_y layout_z
// (double) plus, for planar layouts, texture_u texture_v (float). face: vertex_indices, and for
// layouts of surfaces cut open (torus in E2, H2 in the Poincare disk) texcoord, 6 floats per face
// (u v per corner, in [0, 1]), which MeshLab reads as wedge texture coordinates.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/compact_mesh.h"
#include "ricci/ricci_flow.h"

namespace ricci::cli {

struct ResultLayout {
  std::vector<Eigen::Vector3d> position;  //!< empty: no layout
  std::vector<Eigen::Vector2d> texture;   //!< empty: no texture coordinates
  //! Per face and corner (surfaces cut open): empty, or the face property texcoord.
  std::vector<std::array<Eigen::Vector2d, 3>> wedge_texture;
};

//! \throws IoError when the file cannot be written.
void write_result_ply(const std::string& path, const CompactMesh& mesh, const FlowResult& result,
                      const ResultLayout& layout, bool ascii);

}  // namespace ricci::cli
