// Connectivity of a manifold triangle mesh as flat index arrays, and edge flips.
//
// Corners of face f are 0, 1, 2 with vertices face_vertex(f, c). Halfedge h = 3 f + c is the
// edge opposite corner c, oriented from corner c+1 to corner c+2 (indices mod 3). Flips change
// faces and edges in place; the number of vertices, edges and faces, the boundary and the
// topology stay, and so do edge indices (a flipped edge keeps its index).
#pragma once

#include <array>
#include <string>
#include <vector>

namespace ricci {

class Triangulation {
 public:
  int num_vertices() const { return num_vertices_; }
  int num_faces() const { return static_cast<int>(faces_.size()); }
  int num_edges() const { return static_cast<int>(edge_vertices_.size()); }
  int num_halfedges() const { return 3 * num_faces(); }

  const std::vector<std::array<int, 3>>& faces() const { return faces_; }
  int face_vertex(int f, int corner) const { return faces_[f][corner]; }

  //! Edge opposite corner c of face f.
  int face_edge(int f, int corner) const { return face_edges_[f][corner]; }
  const std::array<int, 3>& face_edges(int f) const { return face_edges_[f]; }
  //! Endpoints of edge e (smaller index first).
  const std::array<int, 2>& edge_vertices(int e) const { return edge_vertices_[e]; }
  //! The halfedge of edge e's other face, or -1 on the boundary.
  int twin(int halfedge) const { return twin_[halfedge]; }
  //! Tail and head vertex of a halfedge.
  int halfedge_tail(int h) const { return faces_[h / 3][(h % 3 + 1) % 3]; }
  int halfedge_head(int h) const { return faces_[h / 3][(h % 3 + 2) % 3]; }
  //! A halfedge of edge e (in its first face).
  int edge_halfedge(int e) const;

  bool is_boundary_vertex(int v) const { return boundary_vertex_[v]; }
  bool is_boundary_edge(int e) const { return edge_faces_[e][1] < 0; }
  //! The (one or two) faces of edge e; the second is -1 on the boundary.
  const std::array<int, 2>& edge_faces(int e) const { return edge_faces_[e]; }

  //! Boundary loops as vertex cycles, each in the orientation of its faces.
  const std::vector<std::vector<int>>& boundary_loops() const { return boundary_loops_; }
  int num_boundary_loops() const { return static_cast<int>(boundary_loops_.size()); }
  bool is_closed() const { return boundary_loops_.empty(); }
  //! Genus 0 with one boundary loop.
  bool is_disk() const { return num_boundary_loops() == 1 && genus() == 0; }

  //! chi = V - E + F.
  int euler_characteristic() const { return num_vertices() - num_edges() + num_faces(); }
  //! g from chi = 2 - 2g - b.
  int genus() const { return (2 - euler_characteristic() - num_boundary_loops()) / 2; }
  //! Human readable topology, e.g. "closed genus-2 surface" or "disk".
  std::string topology_name() const;

  //! The two vertices opposite interior edge e (in its first and second face).
  std::array<int, 2> opposite_vertices(int e) const;
  //! Whether flip(e) can replace e: an interior edge between two faces whose other four sides are
  //! four edges (not where e's faces wrap around a vertex of degree 1 or 2 and meet twice).
  bool flips_to_triangles(int e) const;

  //! The connectivity of faces over vertices 0..num_vertices-1 (a subdivision's, say), with no
  //! geometry checked. \throws InvalidMeshError as build_connectivity does.
  static Triangulation from_faces(int num_vertices, std::vector<std::array<int, 3>> faces);

 protected:
  //! Replaces interior edge e, the diagonal of the quadrilateral of its two faces, by the other
  //! diagonal. Returns false (and changes nothing) where !flips_to_triangles(e). The new
  //! diagonal may join vertices another edge joins already, or a vertex to itself (a loop, where
  //! both opposite vertices coincide; its faces then have two corners at that vertex). (Public in
  //! IntrinsicTriangulation only: a CompactMesh's input lengths belong to its edges.)
  bool flip(int e);

  Triangulation() = default;
  //! Builds edges, twins and boundary loops from faces_ and checks the connectivity.
  //! \throws InvalidMeshError for non-manifold edges or vertices, inconsistently oriented
  //!   faces, several connected components.
  void build_connectivity(int num_vertices);
  //! The same, with halfedges paired by keys instead of their vertices: halfedge h belongs to the
  //! edge of the other halfedge with keys halfedge_keys[h] (tail, head) reversed. Keys are in
  //! 0..num_keys-1. Two edges may then join the same two vertices (the double of a surface whose
  //! boundary vertices are joined by an interior edge has two such edges).
  void build_connectivity(int num_vertices, const std::vector<std::array<int, 2>>& halfedge_keys,
                          int num_keys);

  std::vector<std::array<int, 3>> faces_;
  std::vector<std::array<int, 2>> edge_vertices_;

 private:
  void connect(int num_vertices, const std::vector<std::array<int, 2>>* keys, int num_keys);
  void build_edges(const std::vector<std::array<int, 2>>* keys, int num_keys);
  void check_manifold_vertices();
  void check_connected();
  void build_boundary_loops();
  void link_twins(int e);

  int num_vertices_ = 0;
  std::vector<std::array<int, 3>> face_edges_;
  std::vector<std::array<int, 2>> edge_faces_;
  std::vector<int> twin_;
  std::vector<char> boundary_vertex_;
  std::vector<std::vector<int>> boundary_loops_;
};

//! A triangulation of the same vertices whose edges can be flipped: the flow's, which starts as a
//! copy of the input's connectivity.
class IntrinsicTriangulation : public Triangulation {
 public:
  explicit IntrinsicTriangulation(const Triangulation& t) : Triangulation(t) {}
  using Triangulation::flip;
};

}  // namespace ricci
