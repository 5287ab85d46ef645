// The steps of repair_mesh (repair.h) and what they share (not installed API).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/repair/repair_report.h"

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

//! The uses of one edge, in face order.
class EdgeUses {
 public:
  EdgeUses(const EdgeUse* first, size_t size) : first_(first), size_(size) {}
  size_t size() const { return size_; }
  const EdgeUse& operator[](size_t i) const { return first_[i]; }
  const EdgeUse* begin() const { return first_; }
  const EdgeUse* end() const { return first_ + size_; }

 private:
  const EdgeUse* first_;
  size_t size_;
};

//! Every edge of a face list with the faces that use it: one sort of the faces' 3 F edge uses by
//! edge_key (a hash map of vectors cost 0.4 s per build on a 267k-face scan; this 30 ms).
class EdgeMap {
 public:
  explicit EdgeMap(const std::vector<Face>& faces);
  size_t num_edges() const { return start_.size() - 1; }
  std::uint64_t key(size_t edge) const { return keys_[start_[edge]]; }
  EdgeUses uses(size_t edge) const {
    return {uses_.data() + start_[edge], start_[edge + 1] - start_[edge]};
  }
  //! The edge that face f's corners c, c + 1 span.
  size_t edge_of(int f, int c) const { return edge_of_use_[3 * static_cast<size_t>(f) + c]; }

 private:
  std::vector<size_t> edge_of_use_;  // per face corner 3 f + c
  std::vector<std::uint64_t> keys_;  // per use, sorted
  std::vector<EdgeUse> uses_;        // in the order of keys_
  std::vector<size_t> start_;        // per edge, its first use; one past the last at the end
};

//! The pairs of faces glued across an edge: two faces that traverse it in opposite ways. Where
//! more than two faces share the edge (non-manifold), they are paired in file order and the rest
//! cut off.
std::vector<std::pair<EdgeUse, EdgeUse>> glued_pairs(const EdgeUses& uses);

//! The report's entry for vertices joined at one position (drop_degenerate's `join`).
inline constexpr const char* kJoinedVertices = "vertices at one position joined";

//! Collapses edges of zero length (relative to the mesh's size) and, with `join`, joins the ends
//! of edges at exactly the same two positions (as an STL file's corners are read: a triangle soup
//! is one surface), then drops the faces that repeat a vertex, and exact duplicates.
//! `represented_by` receives each vertex's surviving vertex (the smallest of those joined).
std::vector<Face> drop_degenerate(const std::vector<Eigen::Vector3d>& p,
                                  const std::vector<std::array<int, 3>>& input,
                                  std::vector<int>& represented_by, Reporter& reporter, bool join);

//! Makes the orientation agree across every glued edge, keeping each component's majority.
//! \throws InvalidMeshError for a component that is not orientable.
void orient(std::vector<Face>& faces, Reporter& reporter);

//! Removes caps: the face across the cap's longest edge is split at the cap's middle vertex (the
//! two halves tile it), and the cap dropped; a cap on the boundary is dropped. Caps that the
//! splits do not remove (they split one another in turn) are dropped, and any face the splits
//! made twice.
void remove_caps(const std::vector<Eigen::Vector3d>& p, std::vector<Face>& faces,
                 Reporter& reporter);

}  // namespace ricci::detail
