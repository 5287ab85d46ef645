// The compact mesh the numerics run on: the triangulation plus the input geometry, built once
// and checked for the conditions the flow needs (manifold, one component, no degenerate faces).
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ricci/mesh/triangulation.h"

namespace ricci {

//! The angle between two vectors in 3D, in [0, pi]; accurate near 0 and pi too (from the sine and
//! the cosine together, where acos of their quotient of norms loses digits).
inline double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

class CompactMesh : public Triangulation {
 public:
  //! Builds and validates the mesh.
  //! \throws InvalidMeshError for non-finite coordinates, out-of-range indices, degenerate,
  //!   zero-area or duplicate faces, unreferenced vertices, non-manifold edges or vertices,
  //!   inconsistently oriented faces, several connected components, an empty mesh.
  CompactMesh(std::vector<Eigen::Vector3d> positions, std::vector<std::array<int, 3>> faces);

  //! The double of a surface with boundary: the mesh and its mirror image glued along the
  //! boundary, a closed surface of genus 2g + b - 1. Vertices: the mesh's, then a copy of each
  //! interior vertex (in order); faces: the mesh's, then their mirror images (in order, reversed);
  //! edges: the mesh's first, numbered alike. Copies sit at their originals' positions.
  //! \pre the mesh has a boundary
  static CompactMesh doubled(const CompactMesh& mesh);

  const std::vector<Eigen::Vector3d>& positions() const { return positions_; }

  //! Input (Euclidean) length of every edge.
  const std::vector<double>& input_lengths() const { return input_lengths_; }
  //! Total Euclidean area of the input.
  double input_area() const;

 private:
  CompactMesh() = default;
  void check_elements();
  void measure_input_lengths();

  std::vector<Eigen::Vector3d> positions_;
  std::vector<double> input_lengths_;
};

}  // namespace ricci
