// A whole mesh as users bring it: repaired (repair.h), each connected component uniformized by its
// own topology (uniformize.h), and the results gathered per vertex of the repaired mesh, with the
// planar charts packed without overlap into [0, 1]^2 (a texture atlas).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ricci/pipeline/uniformize.h"
#include "ricci/repair/repair.h"

namespace ricci {

struct MeshUniformization {
  RepairedMesh mesh;
  std::vector<Uniformization> components;  //!< one per mesh.components
  //! The delivered vertices: the repaired mesh's, then the new vertices of the components whose
  //! result is a common subdivision (common_subdivision.h), component after component.
  std::vector<Eigen::Vector3d> positions;
  //! Per delivered vertex: -1 for the repaired mesh's; for a new vertex the input face it lies in
  //! and its barycentric coordinates at that face's corners (in the order the faces were read,
  //! or reversed where the repair reoriented the face).
  std::vector<int> vertex_input_face;
  std::vector<Eigen::Vector3d> vertex_barycentric;
  //! Per delivered vertex; NaN where a vertex is in no face. New vertices are flat (curvature
  //! 0), with no target; u interpolated along their input edge.
  Eigen::VectorXd u, radius, curvature, target;
  //! Per vertex where its component's layout has one position per vertex (plane, sphere), NaN
  //! elsewhere; empty when no component has one.
  std::vector<Eigen::Vector3d> position;
  //! The delivered faces (the repaired mesh's, or a component's common subdivision), component
  //! after component, and the input face each lies in.
  std::vector<std::array<int, 3>> faces;
  std::vector<int> input_face;
  //! Per delivered face: its component's layout kind, its corners in that layout's model before
  //! any normalization (the plane in the metric's units, the unit disk for the disk target; the
  //! Poincare disk, in the face's chart, on the geodesics: Uniformization::model_corners where
  //! the texture draws some on straight sides; the unit sphere), NaN where the component has no
  //! layout; and its chart (Layout::chart, 0 for a layout in one piece, -1 without a layout),
  //! numbered on from the charts of the components before its own: one number per piece.
  std::vector<LayoutKind> face_layout;
  std::vector<std::array<Eigen::Vector3d, 3>> corners;
  std::vector<int> face_chart;
  //! Per vertex when every component is laid out in the plane with one position per vertex, else
  //! per face corner (faces of sphere components at 0); the charts packed into [0, 1]^2. Empty
  //! when no component has a planar layout.
  TextureCoordinates texture;
  //! Several components with planar layouts: the texture packed from all of them, its pieces
  //! (an atlas component's charts, any other layout whole), its share of [0, 1]^2, and the area
  //! distortion D of all its faces (as AtlasResult::distortion, over the whole texture). Zero
  //! pieces otherwise.
  struct PackedTexture {
    int pieces = 0;
    double utilization = 0;
    double distortion = 0;
    double padding = 0, padding_asked = 0;  //!< as AtlasResult's
    int below_a_texel = 0;                  //!< pieces packed into less than a texel
  } packed;
  //! The atlas target: its cones, on delivered vertices, with their angles in the exact metric.
  std::vector<Cone> cones;
  //! Per component: the delivered index of its first new vertex.
  std::vector<int> new_vertex_base;

  int num_new_vertices() const {
    return static_cast<int>(positions.size() - mesh.positions.size());
  }
  bool converged() const;
  bool valid() const;  //!< every component converged with a valid layout
  //! \throws ConvergenceError or LayoutError naming the first component that failed.
  void require_valid(const std::string& subject = "") const;
};

//! The layout each component will get (planned_layout of its resolved request).
//! \throws InvalidTargetError, InvalidArgumentError as resolve_request does.
std::vector<LayoutKind> planned_layouts(const RepairedMesh& mesh,
                                        const UniformizationOptions& options);

//! Uniformizes every component of the repaired mesh with the options (per-vertex values, the
//! centre and axis vertex and the vertex order are given in the input's vertex numbering).
//! \throws InvalidTargetError, InvalidArgumentError as uniformize() does, naming the component.
MeshUniformization uniformize_mesh(RepairedMesh mesh, const UniformizationOptions& options);

}  // namespace ricci
