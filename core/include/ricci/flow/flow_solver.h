// RicciFlowSolver: the flow's state on one mesh kept between solves (ricci_flow.h has the
// one-shot calls and the algorithm; flow_result.h what a solve is asked and gives).
#pragma once

#include <memory>
#include <string>

#include <Eigen/Core>

#include "ricci/flow/flow_result.h"
#include "ricci/flow/scheme.h"
#include "ricci/flow/target.h"
#include "ricci/linear/vertex_order.h"
#include "ricci/mesh/compact_mesh.h"

namespace ricci {

namespace detail {
struct FlowState;  // flow/flow_state.h
}  // namespace detail

//! The flow on one mesh and conformal structure, kept between solves: the triangulation as
//! flipped, the structure's eta on it, u, and the Hessian's pattern with its symbolic analysis
//! (reused while neither the triangulation nor the set of free vertices changes). A solve starts
//! where the last one ended: solving for a target near the last one takes few iterations.
class RicciFlowSolver {
 public:
  //! Hessians of kNestedDissectionRows rows or more on the mesh's own triangulation (any free
  //! set; not after flips, not S2's H^2 + mu I, not with LDL^T) are analysed in `order`
  //! (vertex_order.h), or where that is empty or for another number of vertices, in one the
  //! solver starts finding at once from the mesh's vertex graph (not in S2, nor with LDL^T).
  //! \throws InvalidArgumentError when the structure was built for another mesh, or the options
  //!   are out of range.
  RicciFlowSolver(const CompactMesh& mesh, const ConformalStructure& structure,
                  FlowOptions options = {}, VertexOrder order = {});
  ~RicciFlowSolver();
  RicciFlowSolver(const RicciFlowSolver&) = delete;
  RicciFlowSolver& operator=(const RicciFlowSolver&) = delete;

  //! Runs the flow to `target` from the current state. With `start`, first walks u towards it in
  //! the longest valid steps (with flips when they are on; Ptolemy flips keep the conformal
  //! class), then Newton. With flips when needed, the progress callback may see the iteration at
  //! which flips began twice (before and after them).
  //! Never throws for non-convergence: the result says why.
  //! \throws InvalidTargetError for a target that admits no flow.
  FlowResult solve(const TargetCurvature& target, const Eigen::VectorXd* start = nullptr);

  //! Runs the Euclidean Yamabe flow to the metric whose boundary loops are circles: the interior
  //! curvature as in `target`, at each boundary vertex the turning of a circle through its loop's
  //! current chords (circle_boundary_target, presets.h; positive on loop `outer_loop`, negative on
  //! the others). One solve: the boundary target's change with u is part of the Jacobian, singular
  //! at the solution along the disk's Moebius maps, so the steps are Levenberg-Marquardt ones,
  //! solved by MINRES preconditioned with a factorization of H (kept while MINRES stays short).
  //! The result's target is the boundary curvature reached. Never throws for non-convergence.
  //! \throws InvalidArgumentError for another geometry or scheme, a closed surface or u held
  //!   fixed; InvalidTargetError as solve().
  FlowResult solve_circle_domain(const TargetCurvature& target, int outer_loop);

  //! EdgeFlips::WhenNeeded: with defer, a solve stops where Newton would start flips
  //! (FlowStop::FlipsNeeded), leaving the caller to choose another way or restart with them. (A
  //! walk to a start with u held fixed somewhere still turns flips on at once; no deferred solve
  //! has a start.)
  void defer_flips(bool defer);

  //! The caller flows on the surface doubled along its boundary where a solve stalls at the
  //! boundary's triangles (where every edge flips): a solve then stops after 3 short steps blocked
  //! there with the residual down by less than a tenth, not 10.
  void double_next(bool next);

  //! Back to the input triangulation, the input structure and u0 (with flips on from the start
  //! after restart_with_flips()).
  void restart();
  //! restart(), and from now on edge flips on from the start, as with EdgeFlips::Always; the next
  //! solve reports them needed from its iteration 0, because of `why`.
  void restart_with_flips(const std::string& why);

 private:
  std::unique_ptr<detail::FlowState> state_;
};

}  // namespace ricci
