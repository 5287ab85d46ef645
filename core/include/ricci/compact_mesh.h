// The compact mesh the numerics run on: index arrays built once, checked for the
// conditions the flow needs (manifold, one component, no degenerate faces, ...).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ricci {

//! Triangle mesh connectivity and input geometry as flat index arrays.
//!
//! Corners of face f are 0, 1, 2 with vertices faces[f][c]. Halfedge h = 3 f + c is the
//! edge opposite corner c, oriented from faces[f][c+1] to faces[f][c+2] (indices mod 3).
class CompactMesh {
 public:
  //! Builds and validates the mesh.
  //! \throws InvalidMeshError for non-finite coordinates, out-of-range indices, degenerate,
  //!   zero-area or duplicate faces, unreferenced vertices, non-manifold edges or vertices,
  //!   inconsistently oriented faces, several connected components, an empty mesh.
  CompactMesh(std::vector<Eigen::Vector3d> positions, std::vector<std::array<int, 3>> faces);

  int num_vertices() const { return static_cast<int>(positions_.size()); }
  int num_faces() const { return static_cast<int>(faces_.size()); }
  int num_edges() const { return static_cast<int>(edge_vertices_.size()); }
  int num_halfedges() const { return 3 * num_faces(); }

  const std::vector<Eigen::Vector3d>& positions() const { return positions_; }
  const std::vector<std::array<int, 3>>& faces() const { return faces_; }
  int face_vertex(int f, int corner) const { return faces_[f][corner]; }

  //! Edge opposite corner c of face f.
  int face_edge(int f, int corner) const { return face_edges_[f][corner]; }
  //! Endpoints of edge e (smaller index first).
  const std::array<int, 2>& edge_vertices(int e) const { return edge_vertices_[e]; }
  //! The halfedge of edge e's other face, or -1 on the boundary.
  int twin(int halfedge) const { return twin_[halfedge]; }
  //! Tail and head vertex of a halfedge.
  int halfedge_tail(int h) const { return faces_[h / 3][(h % 3 + 1) % 3]; }
  int halfedge_head(int h) const { return faces_[h / 3][(h % 3 + 2) % 3]; }

  bool is_boundary_vertex(int v) const { return boundary_vertex_[v]; }
  bool is_boundary_edge(int e) const { return edge_faces_[e][1] < 0; }
  //! The (one or two) faces of edge e; the second is -1 on the boundary.
  const std::array<int, 2>& edge_faces(int e) const { return edge_faces_[e]; }

  //! Boundary loops as vertex cycles, each in the orientation of its faces.
  const std::vector<std::vector<int>>& boundary_loops() const { return boundary_loops_; }
  int num_boundary_loops() const { return static_cast<int>(boundary_loops_.size()); }
  bool is_closed() const { return boundary_loops_.empty(); }

  //! chi = V - E + F.
  int euler_characteristic() const { return num_vertices() - num_edges() + num_faces(); }
  //! g from chi = 2 - 2g - b.
  int genus() const { return (2 - euler_characteristic() - num_boundary_loops()) / 2; }

  //! Input (Euclidean) length of every edge.
  const std::vector<double>& input_lengths() const { return input_lengths_; }
  //! Total Euclidean area of the input.
  double input_area() const;

  //! Human readable topology, e.g. "closed genus-2 surface" or "disk".
  std::string topology_name() const;

 private:
  void check_elements();
  void build_edges();
  void check_manifold_vertices();
  void check_connected();
  void build_boundary_loops();

  std::vector<Eigen::Vector3d> positions_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<std::array<int, 3>> face_edges_;
  std::vector<std::array<int, 2>> edge_vertices_;
  std::vector<std::array<int, 2>> edge_faces_;
  std::vector<int> twin_;
  std::vector<char> boundary_vertex_;
  std::vector<std::vector<int>> boundary_loops_;
  std::vector<double> input_lengths_;
};

}  // namespace ricci
