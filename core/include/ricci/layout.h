// Layout of a flat (E2) metric of a disk into the plane.
//
// Edge directions are integrated across the faces by the corner angles (errors add along a
// path, they do not multiply), then positions are the sparse least-squares fit to every face's
// edge vectors (DESIGN.md, "Layout, measured").
#pragma once

#include <vector>

#include <Eigen/Core>

#include "ricci/linear_solver.h"
#include "ricci/triangulation.h"

namespace ricci {

struct PlanarLayout {
  std::vector<Eigen::Vector2d> position;  //!< per vertex, in the units of the metric
  int num_flipped_faces = 0;              //!< laid-out faces with non-positive signed area
  double max_relative_length_error = 0;   //!< max | |x_j - x_i| / l_ij - 1 | over edges
};

//! Lays out a disk with the given flat edge lengths, centred at the vertices' centroid, with
//! the first edge of face 0 along +x.
//! \pre the lengths are a valid E2 metric, flat (angle sum 2 pi) at interior vertices.
//! \throws InvalidArgumentError when the mesh is not a disk or lengths are invalid.
PlanarLayout layout_disk(const Triangulation& mesh, const std::vector<double>& lengths,
                         LinearSolverKind solver = LinearSolverKind::Cholmod);

//! Faces of `mesh` whose corners at `position` have non-positive signed area. With a
//! triangulation other than the one laid out (the input's, after flips), this counts the input
//! triangles the layout turns over.
int count_flipped_faces(const Triangulation& mesh, const std::vector<Eigen::Vector2d>& position);

//! The positions scaled and shifted into [0, 1]^2 with the aspect ratio kept: texture
//! coordinates.
std::vector<Eigen::Vector2d> normalized_texture_coordinates(
    const std::vector<Eigen::Vector2d>& position);

}  // namespace ricci
