// Edge flips that keep the triangulation (power) Delaunay for the current metric (paper, last
// paragraph; Gu, Luo, Sun, Wu for Yamabe flow with surgery).
//
// One criterion for every scheme and geometry: interior edge ij is (power) Delaunay when its
// off-diagonal Hessian entry dK_i/du_j is <= 0, i.e. the dual edge of the power diagram has
// non-negative length (paper, Section 4). For Euclidean Yamabe this is cot a + cot b >= 0.
//
// A flipped edge gets a new eta. Where all four vertices of the quadrilateral have eps = 0
// (Yamabe), the lambda-lengths lambda = sqrt(2 eta) follow Ptolemy's relation, which keeps the
// discrete conformal class (Penner coordinates); otherwise eta solves the length law for the
// current length of the new diagonal, which keeps the metric.
//
// A new diagonal may join two vertices that another edge already joins: intrinsic triangulations
// can need such multi-edges (both sides of a thin ear). Everything downstream works per edge
// index, halfedge or face corner, never by vertex pair. With FlowOptions::loops, an edge may also
// join a vertex to itself, and a face have two corners at one vertex.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "flow/metric.h"
#include "ricci/flow/flow_result.h"
#include "ricci/flow/scheme.h"
#include "ricci/mesh/triangulation.h"

namespace ricci {

//! True for a boundary edge, or an interior edge whose dK_i/du_j is at most `tolerance` times
//! the size of its faces' angle derivatives. \pre state.valid() around e
bool is_delaunay(const Triangulation& mesh, const MetricState& state, int e,
                 double tolerance = 1e-10);

//! Euclidean or hyperbolic Yamabe: every vertex has eps = 0, every flip is a Ptolemy flip, and a
//! triangulation that is Delaunay by is_ptolemy_delaunay() has only valid triangles, whatever u.
//! E2: Springborn 2020, through the decorated ideal hyperbolic surface of the lambda-lengths. H2:
//! the chords 2 sinh(l/2) = 2 lambda e^((ui+uj)/2) scale as Euclidean Yamabe lengths, so the
//! same holds for them; chords that satisfy the triangle inequality make a valid hyperbolic
//! triangle (2 sinh is superadditive), and Ptolemy's relation holds for the chords of four points
//! on a hyperbolic circle (in the hyperboloid model they span a Euclidean plane), so a Ptolemy
//! flip is the geometric one where the flow meets it.
bool all_ptolemy(const ConformalStructure& structure);

//! The Delaunay criterion from the lengths alone: the cosines of the two angles opposite e in the
//! triangles of the edges' chords (their lengths in E2), by the law of cosines, sum to at least
//! -tolerance. On valid Euclidean triangles this is alpha + beta <= pi, is_delaunay() for
//! Euclidean Yamabe; it is also defined where lengths violate the triangle inequality, as the
//! Delaunay criterion of the decorated ideal triangulation.
bool is_ptolemy_delaunay(const Triangulation& mesh, Geometry geometry, const MetricState& state,
                         int e, double tolerance = 1e-10);

struct FlipReport {
  int flips = 0;                   //!< edges flipped
  std::vector<EdgeFlip> sequence;  //!< the flipped edges, in order
  int blocked = 0;  //!< non-Delaunay edges that could not be flipped (non-convex quadrilateral,
                    //!< a loop not asked for, two sides one edge, eta <= 0 or an invalid
                    //!< triangle after)
  int loops_refused = 0;  //!< of them, flips to an edge from a vertex to itself (a loop) not made
};

//! The new diagonal k-l of an isometric flip, from the quadrilateral's sides k-a, a-l, l-b, b-k
//! and its diagonal a-b (EdgeFlip::lambda's order): the quadrilateral unfolded at a. The flips of
//! make_input_delaunay and the common subdivision's charts of its faces both take it from here.
double isometric_flip_diagonal(const std::array<double, 5>& sides);

//! Yamabe at u0 = 0 (lambda = sqrt(2 eta): in E2 the input's length, in S2 half the chord of the
//! scaled input length read as an arc): flips the Euclidean metric of the lambda-lengths to its
//! intrinsic Delaunay triangulation, each flip isometric (the new diagonal the
//! unfolded quadrilateral's), recorded with EdgeFlip::isometric.
FlipReport make_input_delaunay(IntrinsicTriangulation& mesh, ConformalStructure& structure);

//! Flips non-Delaunay edges until none is left (or max_flips is reached), updating the flipped
//! edges' eta in `structure` and the lengths and angles in `state`. A state with invalid
//! triangles is flipped by is_ptolemy_delaunay() when all_ptolemy(structure), and left as it is
//! otherwise; it ends valid unless a flip was refused (blocked: one that would make a loop, an
//! edge from a vertex to itself, unless `loops` and the flip is a Ptolemy flip; one whose
//! quadrilateral has two sides that are one edge), or an invalid triangle has a boundary edge
//! (which no flip removes). \pre state == evaluate_metric(mesh, structure, u)
FlipReport make_delaunay(IntrinsicTriangulation& mesh, ConformalStructure& structure,
                         const Eigen::VectorXd& u, MetricState& state, int max_flips, bool loops);

}  // namespace ricci
