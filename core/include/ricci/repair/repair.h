// Repairs that change nothing of the surface, so that real files can be used as they come, and the
// split into connected components, each a checked CompactMesh:
//   - vertices at one position joined where edges of faces have the same two end positions (a
//     triangle soup is one surface; RepairOptions::join_coincident);
//   - edges of zero length ("needles") collapsed, and the faces that then repeat a vertex dropped;
//   - faces that repeat a vertex, and exact duplicate faces (the same three vertices), dropped;
//   - the orientation of each component made consistent (the majority's kept);
//   - non-manifold edges cut open (their faces are not glued across them);
//   - zero-area faces with a vertex inside their longest edge ("caps") removed, the face across
//     that edge split at the vertex (the same triangles of the same plane); zero area: twice the
//     area under 1e-12 of the longest side squared, or sides whose slack a + b - c is under 1e-14
//     of c (no metric starts from such a face in double precision);
//   - non-manifold vertices split into one copy per fan of faces (copies come after the input's
//     vertices).
// Unreferenced vertices stay where they are and belong to no component.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/compact_mesh.h"
#include "ricci/repair/repair_report.h"

namespace ricci {

//! One connected component of the repaired surface.
struct MeshComponent {
  CompactMesh mesh;
  std::vector<int> vertex;  //!< per component vertex: the repaired mesh's vertex
  std::vector<int> face;    //!< per component face: the input face it lies in
};

struct RepairedMesh {
  //! The input's vertices in their order, then the copies made by splitting vertices.
  std::vector<Eigen::Vector3d> positions;
  //! Per vertex: the input vertex it is, or copies.
  std::vector<int> original;
  //! Per vertex: the vertex whose results it takes (itself, the vertex a needle collapsed it
  //! onto, or, for a vertex joined to others at its position, the copy its own faces went to where
  //! a non-manifold edge was cut open again); -1 where the vertex is in no face. A vertex that
  //! faces hold is delivered with its own results whatever this says (MeshUniformization).
  std::vector<int> represented_by;
  std::vector<MeshComponent> components;  //!< in the order of their first input face
  RepairReport report;
  int num_input_vertices = 0;
  int num_unreferenced = 0;  //!< input vertices in no face (kept, with no result)
};

struct RepairOptions {
  //! Refuse instead of repairing: the mesh must be one clean component (CompactMesh's checks).
  bool strict = false;
  //! Join vertices at one position where edges of faces have the same two end positions (a
  //! triangle soup becomes one surface); false: vertices at one position stay apart but for the
  //! ends of zero-length edges, and a mesh cut open (its vertices copied along the cut) stays cut.
  bool join_coincident = true;
};

//! Repairs the faces as read and splits them into components.
//! \throws InvalidMeshError for what cannot be repaired (indices out of range, non-finite
//!   coordinates on a face, no face, a non-orientable component), and with options.strict for
//!   the first defect, as CompactMesh names it.
RepairedMesh repair_mesh(const std::vector<Eigen::Vector3d>& positions,
                         const std::vector<std::array<int, 3>>& faces,
                         const RepairOptions& options = {});

}  // namespace ricci
