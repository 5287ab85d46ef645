// What both routes of the common subdivision share: the input's vertices placed first, a face of
// the flips' triangulation cut into pieces by the input's edges, and points on a laid-out side.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/flow_result.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/mesh/geometry.h"
#include "ricci/subdivision/subdivided_mesh.h"
#include "subdivision/input_overlay.h"

namespace ricci::detail {

// The input's vertices as the subdivision's first ones: their positions, u (room for `extra`
// new vertices' u after them), and each one's first input face with a unit coordinate there.
void place_input_vertices(const CompactMesh& mesh, const FlowResult& result, int extra,
                          CommonSubdivision& out);

// Barycentric coordinates (1 - t, t) of a point on edge (v0, v1), from the overlay's convention
// to the realization of the metric with conformal factor u.
double realize(const InputOverlay& overlay, double t, int v0, int v1, const Eigen::VectorXd& u);

// The point with barycentric coordinates (1 - t, t) between two corners of a laid-out triangle
// of the final metric: straight in the plane, the chord's central projection on the sphere, and
// through the hyperboloid for the Poincare disk.
Eigen::Vector3d between(Geometry g, const Eigen::Vector3d& p, const Eigen::Vector3d& q, double t,
                        DiskSidePoints disk_points);

// The points on the boundary of a face of the overlay's current triangulation, counter-clockwise:
// corner 0, the crossings on its side to corner 1, corner 1, ...
struct BoundaryPoint {
  int corner = -1;    // a corner of the face, or
  int crossing = -1;  // a crossing of the overlay on side `side`
  int side = 0;       // from corner `side` to corner side + 1
};

// A piece of a face of the current triangulation between the input's edges: its boundary points
// counter-clockwise and, per side (from point i to point i + 1), the input edge it runs along, or
// -1 on an arc of the face's side that is no input edge.
struct FacePiece {
  std::vector<int> points;
  std::vector<int> along;
  std::vector<char> arc;  // per side: an arc of the face's side (else an input edge inside it)
  int input_face = -1;
};

struct FaceCut {
  std::vector<BoundaryPoint> points;
  std::vector<FacePiece> pieces;
};

// Cuts face `face` of the overlay's current triangulation by the input's edges.
FaceCut cut_face(const InputOverlay& overlay, int face);

}  // namespace ricci::detail
