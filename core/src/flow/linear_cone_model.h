// The linear model of the Euclidean Yamabe flow at u = 0, for cone placement
// (ricci/flow/cone_placement.h has the mathematics): H, the Hessian of the input metric's
// intrinsic Delaunay triangulation, factored once over the free vertices (the interior ones; on a
// closed surface all but one, pinned); g = R(-K0); and the columns R(e_v) of the vertices tried as
// cones, each one back-solve, kept side by side in one dense block.
//
// Beside each column the model keeps its area-weighted sums with g and, once a set pairs them,
// with the other columns, so that the distortion D of any cone set is a (|C| x |C|) quadratic
// form: a cone set is judged without forming u over the vertices, which costs |C| vertex-long
// passes.
#pragma once

#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "flow/delaunay.h"
#include "flow/hessian.h"
#include "ricci/linear/linear_solver.h"
#include "ricci/mesh/compact_mesh.h"

namespace ricci {

//! Per vertex: a third of the areas of its input faces, summing to 1.
Eigen::VectorXd normalized_vertex_areas(const CompactMesh& mesh);
//! sqrt(sum_i A_i (u_i - mean u)^2), the mean A-weighted: D of ricci/flow/cone_placement.h.
double area_weighted_deviation(const Eigen::VectorXd& area, const Eigen::VectorXd& u);

//! Reciprocal condition number below which a held system counts as singular (no flat metric
//! with u = 0 at its cones); the cones of a real search are far from it.
inline constexpr double kSingular = 1e-12;

class LinearConeModel {
 public:
  //! `by_solve_from`: the cones from which u and a column's sums are solved for rather than
  //! summed over the columns (0: where that costs less, from the factor's fill and the columns'
  //! size). `weighed_columns`: the most columns' R(A col) kept (0: as many as kWeighedBytes hold).
  //! \throws SolverError when the Laplacian is not positive definite (degenerate triangles).
  LinearConeModel(const CompactMesh& mesh, LinearSolverKind kind, size_t by_solve_from = 0,
                  long weighed_columns = 0);

  //! The input metric's curvature per vertex (its intrinsic Delaunay triangulation's).
  const Eigen::VectorXd& curvature0() const { return k0_; }
  //! Per vertex: a third of the areas of its input faces, summing to 1.
  const Eigen::VectorXd& area() const { return area_; }
  int back_solves() const { return back_solves_; }
  bool factored() const { return factored_; }

  //! The solution of a cone set with u = 0 held at its cones: their curvatures k and, on a closed
  //! surface, the constant c of u = g + sum_j k_j R(e_j) + c; and D of that u.
  struct Solution {
    Eigen::VectorXd k;
    double c = 0;
    double d = 0;
    bool ok = false;  //!< false: no flat metric with u = 0 at these cones (a singular system)
  };
  Solution held(const std::vector<int>& cones);
  //! u per vertex of a held solution (exactly 0 at the cones).
  Eigen::VectorXd u(const std::vector<int>& cones, const Solution& s);
  //! Whether u of a set of this many cones is solved for (one back-solve) rather than summed from
  //! their columns.
  bool u_by_solve(size_t cones) const { return cones >= by_solve_from_; }
  //! u of several held solutions (each of a set with u_by_solve), in one multi-column solve.
  std::vector<Eigen::VectorXd> u(const std::vector<std::vector<int>>& sets,
                                 const std::vector<const Solution*>& solutions);
  //! u per vertex with the cones' curvatures given, u free at them (the mean 0 on a closed
  //! surface).
  Eigen::VectorXd prescribed(const std::vector<int>& cones, const Eigen::VectorXd& k);

  //! D of u = g + G k (+ c) for a cone set's curvatures k, from the area-weighted sums: O(|C|^2).
  double distortion(const std::vector<int>& cones, const Eigen::VectorXd& k) const;
  //! D from the sums a set's k makes: sum_ij k_i k_j (A col_i . col_j), sum_i k_i (A col_i . g)
  //! and sum_i k_i (A . col_i).
  double distortion(double quadratic, double with_g, double sum) const;
  //! D^2 of a cone set's curvatures k as k^T q k + 2 b^T k + (D^2 of g): the pair (q, b), q
  //! positive definite (on the plane sum k = 2 pi chi of a closed surface).
  std::pair<Eigen::MatrixXd, Eigen::VectorXd> distortion_form(const std::vector<int>& cones) const;
  //! v's column's area-weighted sums with each of these cones' columns (all solved), and with
  //! itself last: a row of the quadratic form.
  Eigen::VectorXd gram_with(int v, const std::vector<int>& cones) const;
  //! v's column's area-weighted sum, and its sum with g (v's column solved).
  double column_sum(int v) const { return sum_[slot_of_[v]]; }
  double column_with_g(int v) const { return with_g_[slot_of_[v]]; }
  //! The held system of a cone set (its columns solved): the matrix of R(e_j)[c_i], bordered on
  //! a closed surface by the constant c (sum k = 2 pi chi), and its right-hand side -g at the
  //! cones; the solution (k, c) of a solve of it, with its D.
  std::pair<Eigen::MatrixXd, Eigen::VectorXd> system(const std::vector<int>& cones);
  Solution solution(const std::vector<int>& cones, const Eigen::VectorXd& x) const;
  //! R(e_column)[row] (column's column solved): the held system's entry.
  double entry(int row, int column) const { return columns_(row, slot_of_[column]); }
  //! g per vertex: u with no cone.
  const Eigen::VectorXd& g() const { return g_; }
  bool closed() const { return mesh_.is_closed(); }
  int euler_characteristic() const { return mesh_.euler_characteristic(); }

  //! Computes the columns of these vertices that are missing, in one multi-column solve (each
  //! column's forward solve over the supernodes its row reaches, the backward solves together);
  //! 0 for a vertex without a row.
  void solve_columns(const std::vector<int>& vertices);
  //! Columns of vertices not in the list are dropped (their room is reused).
  void keep_only(const std::vector<int>& vertices);

 private:
  Eigen::VectorXd combination(const std::vector<int>& cones, const Eigen::VectorXd& k);  // g + G k
  // Per set, sum_j k_j e_(cones_j) over the free rows: the right-hand sides whose solves are G k.
  SparseMatrix curvatures(const std::vector<std::vector<int>>& sets,
                          const std::vector<const Eigen::VectorXd*>& k) const;
  // g + G k made s's u: its constant added (the mean taken out on a closed surface without
  // cones), exactly 0 at the cones.
  void held_at_cones(const std::vector<int>& cones, const Solution& s, Eigen::VectorXd& u) const;
  Eigen::VectorXd scatter(const Eigen::VectorXd& x) const;
  int store(int v, const Eigen::VectorXd& column);

  const CompactMesh& mesh_;
  IntrinsicTriangulation delaunay_;
  LinearSolver solver_;
  std::vector<int> free_index_;
  int rows_ = 0;
  Eigen::VectorXd k0_, g_, area_;
  // Columns R(e_v) side by side; slot_of_[v] is v's, -1 without one.
  Eigen::MatrixXd columns_;
  std::vector<int> slot_of_, vertex_of_slot_, free_slots_;
  // sum A col_a col_b, computed when first asked for (gram_ holds kNotYet until then).
  double gram(int a, int b) const;
  // Column a's sums with every column kept, from one back-solve of R(A col_a), which is kept
  // (within kWeighedBytes) for its sums with the columns solved later.
  void gram_row(int a) const;
  // Slot s's R(A col) dropped (its column replaced or dropped).
  void forget_weighed(int s);
  // Whether another column's R(A col) can be kept.
  bool room_to_weigh() const;
  // Column a's sums with the columns of these slots: by one back-solve (gram_row) where a set
  // first pairs it with many (once per column), else each when first asked for.
  void pair(int a, const std::vector<int>& slots) const;
  // From this many cones (or columns to pair) a back-solve, which reads the factor, costs less
  // than as many vertex-long passes over the columns: u = g + G k, and a column's sums with the
  // others, are then solved for. A back-solve costs about kSolveOverPass passes per factor entry
  // per row, where the passes read the columns from memory: below kCachedColumns bytes of them
  // they are cheaper still. Measured (placement seconds): a 117k-face CAD head, 353 cones, 14
  // instead of 46, the same cones, D, charts and seams (24 with the solves from twice as many
  // cones); CGAL's cheese, about 635 cones, 18 instead of 36 to 50 (rounding took its greedy one
  // other step: 637 cones, D 0.1617, for 633, 0.1620); the cow, whose 2.9k-row columns stay in
  // cache, 0.085 where its greedy's 73 cones were solved for, 0.04 not.
  static constexpr double kSolveOverPass = 2;
  static constexpr double kCachedColumns = 16.0 * 1024 * 1024;
  size_t by_solve_from_ = std::numeric_limits<size_t>::max();
  mutable std::vector<char> row_seen_;  // per slot: distortion() has looked at its sums
  // R(A col) of some columns side by side (scattered to the vertices): a column's whose sums were
  // solved for at once (pair), or that has been summed with about as many columns as a back-solve
  // costs passes (a cone: the sweeps try candidates beside every cone), so that its sum with any
  // other column is a read, sum A col_a col_b = R(A col_a)[b]. Per slot its column here, -1
  // without one; passes: its sums formed by a pass. At most kWeighedBytes of them, first come
  // first kept (two parts placed at once hold twice that).
  static constexpr double kWeighedBytes = 128.0 * 1024 * 1024;
  long max_weighed_ = 0;
  mutable Eigen::MatrixXd weighed_;
  mutable std::vector<int> weighed_of_slot_, free_weighed_;
  mutable std::vector<size_t> passes_;
  static constexpr double kNotYet = std::numeric_limits<double>::quiet_NaN();

  // Area-weighted sums: gram_(i, j) = sum A col_i col_j, sum_(i) = sum A col_i,
  // with_g_(i) = sum A col_i g; and for g alone.
  mutable Eigen::MatrixXd gram_;
  Eigen::VectorXd sum_, with_g_;
  double g_sum_ = 0, g_square_ = 0;
  mutable int back_solves_ = 0;
  bool factored_ = false;
};

}  // namespace ricci
