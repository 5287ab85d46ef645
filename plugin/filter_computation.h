// What the filter computes, apart from any MeshLab API: read a vcg mesh, run the flow and the
// layout the settings ask for, and write the results back. Nothing is written unless everything
// succeeded, so a failed filter leaves the mesh as it was.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <vcg/complex/algorithms/update/color.h>
#include <vcg/complex/complex.h>

#include "filter_settings.h"
#include "ricci/mesh/vcg_adapter.h"
#include "ricci/pipeline/atlas.h"
#include "ricci/pipeline/uniformize.h"
#include "ricci/repair/repair.h"

namespace ricci::plugin {

//! What the filter reads, with the live vertices and faces in storage order ("compact" order).
struct MeshInput {
  std::vector<std::array<int, 3>> faces;  //!< the live faces, on compact vertex indices
  std::vector<int> compact_index;         //!< per slot of the vcg vertex vector; -1 where deleted
  std::vector<char> selected;             //!< vertex selection flags
  std::vector<double> quality;            //!< vertex quality; empty when the mesh has none
  //! Repaired and split into components; its vertices are the compact ones, then copies.
  RepairedMesh repaired;
  //! The first component (the whole mesh when it is one clean component).
  const CompactMesh& mesh() const { return repaired.components.front().mesh; }
};

struct FilterComputation {
  MeshUniformization run;  //!< every component's flow, layout and quality, gathered per vertex

  const Uniformization& uniformization() const { return run.components.front(); }
  const FlowResult& result() const { return uniformization().result; }
  const TextureCoordinates& texture() const { return run.texture; }
  //! Every component's layout has one position per vertex (plane, sphere).
  bool has_vertex_layout() const {
    return !run.position.empty() &&
           std::all_of(run.components.begin(), run.components.end(),
                       [](const Uniformization& u) { return !u.position.empty(); });
  }
  //! The repairs changed the vertices or faces (not only the order of the components' faces):
  //! the mesh is rebuilt when the results are written.
  bool rebuilds(const MeshInput& input) const {
    if (run.positions.size() != input.selected.size() || run.faces.size() != input.faces.size()) {
      return true;
    }
    for (size_t k = 0; k < run.faces.size(); ++k) {
      const int f = run.input_face[k];
      if (f < 0 || f >= static_cast<int>(input.faces.size()) || run.faces[k] != input.faces[f]) {
        return true;
      }
    }
    return false;
  }
};

//! The optional mesh components a computation writes, for the adapter to enable first.
struct WrittenComponents {
  bool quality_and_color = false;
  bool vertex_texcoord = false;
  bool wedge_texcoord = false;
  bool layout_layer = false;  //!< a new layer at the per-vertex layout
};
WrittenComponents written_components(const FilterSettings& settings, const FilterComputation& c);

//! Reads positions, faces, selection and, if has_quality, the quality of the live vertices, and
//! repairs the mesh (repair.h; with repair.strict, refuses one that needs repairs instead).
//! (MeshLab's meshes always carry a quality field; whether it holds data is in the MeshModel's
//! data mask, which the caller passes as has_quality.)
//! \throws InvalidMeshError when the mesh cannot be used.
template <class MeshT>
MeshInput read_mesh_input(const MeshT& m, bool has_quality, const RepairOptions& repair = {}) {
  MeshInput in;
  std::vector<Eigen::Vector3d> positions;
  mesh_arrays_from_vcg(m, positions, in.faces, &in.compact_index);
  in.selected.assign(positions.size(), 0);
  has_quality = has_quality && vcg::tri::HasPerVertexQuality(m);
  if (has_quality) in.quality.assign(positions.size(), 0.0);
  for (size_t i = 0; i < m.vert.size(); ++i) {
    const int v = in.compact_index[i];
    if (v < 0) continue;
    in.selected[v] = m.vert[i].IsS();
    if (has_quality) in.quality[v] = static_cast<double>(m.vert[i].cQ());
  }
  in.repaired = repair_mesh(positions, in.faces, repair);
  return in;
}

//! Runs the flow on every component and lays out its result (atlas.h).
//! \throws the core's errors, ConvergenceError when a flow does not converge, LayoutError when a
//!   layout is not a valid map.
FilterComputation compute(const MeshInput& input, const FilterSettings& settings,
                          const std::function<bool(const FlowProgress&)>& progress = {});

//! Replaces the mesh's faces by the delivered ones and adds the vertex copies the repairs made and
//! the new vertices of a common subdivision, then compacts it: afterwards its live vertices are
//! the delivered ones, in order.
template <class MeshT>
void rebuild_repaired(MeshT& m, const FilterComputation& c) {
  using Allocator = vcg::tri::Allocator<MeshT>;
  using Scalar = typename MeshT::ScalarType;
  Allocator::CompactEveryVector(m);
  const std::vector<Eigen::Vector3d>& p = c.run.positions;
  const size_t live = m.vert.size();
  if (p.size() > live) Allocator::AddVertices(m, p.size() - live);
  for (size_t v = live; v < p.size(); ++v) {
    m.vert[v].P() =
        vcg::Point3<Scalar>(static_cast<Scalar>(p[v].x()), static_cast<Scalar>(p[v].y()),
                            static_cast<Scalar>(p[v].z()));
  }
  for (auto& f : m.face) {
    if (!f.IsD()) Allocator::DeleteFace(m, f);
  }
  auto added = Allocator::AddFaces(m, c.run.faces.size());
  for (const auto& t : c.run.faces) {
    for (int k = 0; k < 3; ++k) added->V(k) = &m.vert[t[k]];
    ++added;
  }
  Allocator::CompactEveryVector(m);
}

//! Writes the results: custom attributes ricci_u, ricci_radius, ricci_curvature, ricci_target
//! (float) and, with a per-vertex layout, ricci_layout (Point3); texture coordinates per vertex
//! (plane) or per wedge (cut open, atlas); vertex quality = u with a color ramp; the atlas's cones
//! as the vertex selection. A mesh the repairs
//! changed is rebuilt first (rebuild_repaired). The caller enables the optional components first
//! (quality, color, vertex or wedge texture coordinates) as written_components() and the settings
//! ask.
template <class MeshT>
void write_results(MeshT& m, const MeshInput& input, const FilterSettings& settings,
                   const FilterComputation& c) {
  using Allocator = vcg::tri::Allocator<MeshT>;
  using Scalar = typename MeshT::ScalarType;
  using Point3 = vcg::Point3<Scalar>;
  std::vector<int> vertex_of_slot = input.compact_index;
  std::vector<int> run_face(c.run.faces.size());  // per live face, in order: its repaired face
  if (c.rebuilds(input)) {  // the live faces become the repaired ones, in their order
    rebuild_repaired(m, c);
    vertex_of_slot.resize(m.vert.size());
    for (size_t i = 0; i < m.vert.size(); ++i) vertex_of_slot[i] = static_cast<int>(i);
    for (size_t k = 0; k < run_face.size(); ++k) run_face[k] = static_cast<int>(k);
  } else {  // the same faces, perhaps in another order (components): matched by input face
    for (size_t k = 0; k < run_face.size(); ++k) {
      run_face[c.run.input_face[k]] = static_cast<int>(k);
    }
  }
  const MeshUniformization& run = c.run;
  auto u = Allocator::template GetPerVertexAttribute<Scalar>(m, "ricci_u");
  auto radius = Allocator::template GetPerVertexAttribute<Scalar>(m, "ricci_radius");
  auto curvature = Allocator::template GetPerVertexAttribute<Scalar>(m, "ricci_curvature");
  auto target = Allocator::template GetPerVertexAttribute<Scalar>(m, "ricci_target");
  const bool vertex_uv = !run.texture.vertex.empty() && settings.write_texture_coordinates;
  const bool wedge_uv = !run.texture.wedge.empty() && settings.write_texture_coordinates;
  if (vertex_uv) vcg::tri::RequirePerVertexTexCoord(m);
  if (wedge_uv) vcg::tri::RequirePerFaceWedgeTexCoord(m);
  if (settings.write_quality) vcg::tri::RequirePerVertexQuality(m);
  std::optional<typename MeshT::template PerVertexAttributeHandle<Point3>> layout;
  if (c.has_vertex_layout()) {
    layout = Allocator::template GetPerVertexAttribute<Point3>(m, "ricci_layout");
  }
  for (size_t i = 0; i < m.vert.size(); ++i) {
    const int v = vertex_of_slot[i];
    if (v < 0) continue;
    auto& vertex = m.vert[i];
    u[vertex] = static_cast<Scalar>(run.u[v]);
    radius[vertex] = static_cast<Scalar>(run.radius[v]);
    curvature[vertex] = static_cast<Scalar>(run.curvature[v]);
    target[vertex] = static_cast<Scalar>(run.target[v]);
    if (layout) {
      const Eigen::Vector3d& p = run.position[v];
      (*layout)[vertex] = Point3(static_cast<Scalar>(p.x()), static_cast<Scalar>(p.y()),
                                 static_cast<Scalar>(p.z()));
    }
    if (vertex_uv) {
      vertex.T().U() = static_cast<Scalar>(run.texture.vertex[v].x());
      vertex.T().V() = static_cast<Scalar>(run.texture.vertex[v].y());
      vertex.T().N() = 0;
    }
    if (settings.write_quality && std::isfinite(run.u[v])) {
      vertex.Q() = static_cast<Scalar>(run.u[v]);  // vertices in no face keep theirs
    }
  }
  if (wedge_uv) {
    size_t f = 0;  // the live faces, in order
    for (auto& face : m.face) {
      if (face.IsD()) continue;
      const auto& uv = run.texture.wedge[run_face[f]];
      for (int k = 0; k < 3; ++k) {
        face.WT(k).U() = static_cast<Scalar>(uv[k].x());
        face.WT(k).V() = static_cast<Scalar>(uv[k].y());
        face.WT(k).N() = 0;
      }
      ++f;
    }
  }
  if (settings.write_quality && vcg::tri::HasPerVertexColor(m)) {
    vcg::tri::UpdateColor<MeshT>::PerVertexQualityRamp(m);
  }
  if (!run.cones.empty()) {  // the atlas's cones become the vertex selection
    std::vector<char> cone(run.positions.size(), 0);
    for (const Cone& k : run.cones) cone[k.vertex] = 1;
    for (size_t i = 0; i < m.vert.size(); ++i) {
      const int v = vertex_of_slot[i];
      if (m.vert[i].IsD() || v < 0) continue;
      if (cone[v]) {
        m.vert[i].SetS();
      } else {
        m.vert[i].ClearS();
      }
    }
  }
}

//! Moves the vertices of `layer`, a copy of the mesh as written (vcg's copy keeps the live
//! vertices in order, and those are the repaired mesh's), to the per-vertex layout (the plane at
//! z = 0, or the unit sphere); a vertex in no face keeps its place.
//! \pre c.has_vertex_layout()
template <class MeshT>
void place_at_layout(MeshT& layer, const FilterComputation& c) {
  using Scalar = typename MeshT::ScalarType;
  for (size_t i = 0; i < layer.vert.size() && i < c.run.position.size(); ++i) {
    const Eigen::Vector3d& p = c.run.position[i];
    if (!p.allFinite()) continue;
    layer.vert[i].P() = vcg::Point3<Scalar>(static_cast<Scalar>(p.x()), static_cast<Scalar>(p.y()),
                                            static_cast<Scalar>(p.z()));
  }
}

}  // namespace ricci::plugin
