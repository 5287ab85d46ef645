// The steps of repair_mesh (repair.h) and what they share (not installed API).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/repair.h"

namespace ricci::detail {

//! A face on its way through the repairs, and the input face it lies in.
struct Face {
  std::array<int, 3> v;
  int input;
};

//! Collects the report's entries in the order they first happen.
class Reporter {
 public:
  void add(const std::string& what, const std::string& element, int index);
  void merge(const Reporter& other);
  RepairReport report;
};

std::uint64_t edge_key(int a, int b);

//! A face's use of an edge: the face traverses it from `from` (corner order v0 -> v1 -> v2).
struct EdgeUse {
  int face;
  int from;
};
using EdgeMap = std::unordered_map<std::uint64_t, std::vector<EdgeUse>>;
EdgeMap edge_uses(const std::vector<Face>& faces);

//! The pairs of faces glued across an edge: two faces that traverse it in opposite ways. Where
//! more than two faces share the edge (non-manifold), they are paired in file order and the rest
//! cut off.
std::vector<std::pair<EdgeUse, EdgeUse>> glued_pairs(const std::vector<EdgeUse>& uses);

//! Collapses edges of zero length (relative to the mesh's size), drops the faces that then repeat
//! a vertex, and exact duplicates. `represented_by` receives each vertex's surviving vertex.
std::vector<Face> drop_degenerate(const std::vector<Eigen::Vector3d>& p,
                                  const std::vector<std::array<int, 3>>& input,
                                  std::vector<int>& represented_by, Reporter& reporter);

//! Makes the orientation agree across every glued edge, keeping each component's majority.
//! \throws InvalidMeshError for a component that is not orientable.
void orient(std::vector<Face>& faces, Reporter& reporter);

//! Removes caps: the face across the cap's longest edge is split at the cap's middle vertex (the
//! two halves tile it), and the cap dropped; a cap on the boundary is dropped.
void remove_caps(const std::vector<Eigen::Vector3d>& p, std::vector<Face>& faces,
                 Reporter& reporter);

}  // namespace ricci::detail
