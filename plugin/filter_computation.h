// What the filter computes, apart from any MeshLab API: read a vcg mesh, run the flow and the
// layout the settings ask for, and write the results back. Nothing is written unless everything
// succeeded, so a failed filter leaves the mesh as it was.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <vcg/complex/algorithms/update/color.h>
#include <vcg/complex/complex.h>

#include "filter_settings.h"
#include "ricci/uniformize.h"
#include "ricci/vcg_adapter.h"

namespace ricci::plugin {

//! The per-vertex data the filter reads, in compact vertex order.
struct MeshInput {
  CompactMesh mesh;
  std::vector<int> compact_index;  //!< per slot of the vcg vertex vector; -1 where deleted
  std::vector<char> selected;      //!< vertex selection flags
  std::vector<double> quality;     //!< vertex quality; empty when the mesh has none
};

struct FilterComputation {
  Uniformization uniformization;  //!< flow, layout and its quality
  TextureCoordinates texture;     //!< per vertex (plane) or per face corner (cut open)

  const FlowResult& result() const { return uniformization.result; }
  //! The layout has one position per vertex (plane, sphere).
  bool has_vertex_layout() const { return !uniformization.position.empty(); }
};

//! The optional mesh components a computation writes, for the adapter to enable first.
struct WrittenComponents {
  bool quality_and_color = false;
  bool vertex_texcoord = false;
  bool wedge_texcoord = false;
  bool layout_layer = false;  //!< a new layer at the per-vertex layout
};
WrittenComponents written_components(const FilterSettings& settings, const FilterComputation& c);

//! Reads positions, faces, selection and, if has_quality, the quality of the live vertices.
//! (MeshLab's meshes always carry a quality field; whether it holds data is in the MeshModel's
//! data mask, which the caller passes as has_quality.)
//! \throws InvalidMeshError when the mesh cannot be used.
template <class MeshT>
MeshInput read_mesh_input(const MeshT& m, bool has_quality) {
  std::vector<int> index;
  CompactMesh mesh = compact_mesh_from_vcg(m, &index);
  MeshInput in{std::move(mesh), std::move(index), {}, {}};
  in.selected.assign(in.mesh.num_vertices(), 0);
  has_quality = has_quality && vcg::tri::HasPerVertexQuality(m);
  if (has_quality) in.quality.assign(in.mesh.num_vertices(), 0.0);
  for (size_t i = 0; i < m.vert.size(); ++i) {
    const int v = in.compact_index[i];
    if (v < 0) continue;
    in.selected[v] = m.vert[i].IsS();
    if (has_quality) in.quality[v] = static_cast<double>(m.vert[i].cQ());
  }
  return in;
}

//! Runs the flow and lays out its result (uniformize.h).
//! \throws the core's errors, and ConvergenceError when the flow does not converge.
FilterComputation compute(const MeshInput& input, const FilterSettings& settings,
                          const std::function<bool(const FlowProgress&)>& progress = {});

//! Writes the results: custom attributes ricci_u, ricci_radius, ricci_curvature, ricci_target
//! (float) and, with a per-vertex layout, ricci_layout (Point3); texture coordinates per vertex
//! (plane) or per wedge (cut open); vertex quality = u with a color ramp. The caller enables the
//! optional components first (quality, color, vertex or wedge texture coordinates) as
//! written_components() and the settings ask.
template <class MeshT>
void write_results(MeshT& m, const MeshInput& input, const FilterSettings& settings,
                   const FilterComputation& c) {
  using Allocator = vcg::tri::Allocator<MeshT>;
  using Scalar = typename MeshT::ScalarType;
  using Point3 = vcg::Point3<Scalar>;
  const FlowResult& result = c.result();
  auto u = Allocator::template GetPerVertexAttribute<Scalar>(m, "ricci_u");
  auto radius = Allocator::template GetPerVertexAttribute<Scalar>(m, "ricci_radius");
  auto curvature = Allocator::template GetPerVertexAttribute<Scalar>(m, "ricci_curvature");
  auto target = Allocator::template GetPerVertexAttribute<Scalar>(m, "ricci_target");
  const bool vertex_uv = !c.texture.vertex.empty() && settings.write_texture_coordinates;
  const bool wedge_uv = !c.texture.wedge.empty() && settings.write_texture_coordinates;
  if (vertex_uv) vcg::tri::RequirePerVertexTexCoord(m);
  if (wedge_uv) vcg::tri::RequirePerFaceWedgeTexCoord(m);
  if (settings.write_quality) vcg::tri::RequirePerVertexQuality(m);
  std::optional<typename MeshT::template PerVertexAttributeHandle<Point3>> layout;
  if (c.has_vertex_layout()) {
    layout = Allocator::template GetPerVertexAttribute<Point3>(m, "ricci_layout");
  }
  for (size_t i = 0; i < m.vert.size(); ++i) {
    const int v = input.compact_index[i];
    if (v < 0) continue;
    auto& vertex = m.vert[i];
    u[vertex] = static_cast<Scalar>(result.u[v]);
    radius[vertex] = static_cast<Scalar>(result.radius[v]);
    curvature[vertex] = static_cast<Scalar>(result.curvature[v]);
    target[vertex] = static_cast<Scalar>(result.target[v]);
    if (layout) {
      const Eigen::Vector3d& p = c.uniformization.position[v];
      (*layout)[vertex] = Point3(static_cast<Scalar>(p.x()), static_cast<Scalar>(p.y()),
                                 static_cast<Scalar>(p.z()));
    }
    if (vertex_uv) {
      vertex.T().U() = static_cast<Scalar>(c.texture.vertex[v].x());
      vertex.T().V() = static_cast<Scalar>(c.texture.vertex[v].y());
      vertex.T().N() = 0;
    }
    if (settings.write_quality) vertex.Q() = static_cast<Scalar>(result.u[v]);
  }
  if (wedge_uv) {
    size_t f = 0;  // compact faces are the live faces in storage order
    for (auto& face : m.face) {
      if (face.IsD()) continue;
      for (int k = 0; k < 3; ++k) {
        face.WT(k).U() = static_cast<Scalar>(c.texture.wedge[f][k].x());
        face.WT(k).V() = static_cast<Scalar>(c.texture.wedge[f][k].y());
        face.WT(k).N() = 0;
      }
      ++f;
    }
  }
  if (settings.write_quality && vcg::tri::HasPerVertexColor(m)) {
    vcg::tri::UpdateColor<MeshT>::PerVertexQualityRamp(m);
  }
}

//! Moves the vertices of `layer`, a copy of the input mesh, to the per-vertex layout (the plane
//! at z = 0, or the unit sphere). \pre c.has_vertex_layout(), and layer has the input's slots.
template <class MeshT>
void place_at_layout(MeshT& layer, const MeshInput& input, const FilterComputation& c) {
  using Scalar = typename MeshT::ScalarType;
  for (size_t i = 0; i < layer.vert.size(); ++i) {
    const int v = input.compact_index[i];
    if (v < 0) continue;
    const Eigen::Vector3d& p = c.uniformization.position[v];
    layer.vert[i].P() = vcg::Point3<Scalar>(static_cast<Scalar>(p.x()), static_cast<Scalar>(p.y()),
                                            static_cast<Scalar>(p.z()));
  }
}

}  // namespace ricci::plugin
