// The held system of a cone set: the linear cone model's system of one set kept as its inverse,
// so that the sets one cone away (one added, one left out, one moved) are solved, and the set
// changed, in O(|C|^2) rather than factored in O(|C|^3); the cone placement's search steps by it
// at hundreds of cones.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "flow/linear_cone_model.h"

namespace ricci {

//! One step of iterative refinement of x, a solution of a x = rhs held through `inverse`, an
//! inverse of a (up to the rounding of the steps that made it): x += inverse (rhs - a x). False,
//! x unchanged, where the residual exceeds `bound` times the system's scale (|a| |x| + |rhs|, in
//! the max norm) or the refined x is not finite: that inverse no longer serves.
bool refine_held_solution(const Eigen::MatrixXd& a, const Eigen::VectorXd& rhs,
                          const Eigen::MatrixXd& inverse, Eigen::VectorXd& x, double bound);

//! A cone set one step away: with v added last (v >= 0, moved < 0), with its i-th cone moved to
//! v (moved = i, v >= 0: it keeps its place), or without its i-th cone (v < 0, moved = i).
std::vector<int> cone_set_step(std::vector<int> cones, int v, int moved);

//! The held system of one cone set (LinearConeModel::held's), kept as its inverse, so that a set
//! that differs from it by one cone (one added, one left out, one moved elsewhere) is solved in
//! O(|C|^2) rather than factored in O(|C|^3); the set itself is changed by such steps at that
//! cost too, its solution refined every so often, and factored afresh where it has drifted. The
//! cones keep their order: a cone left out leaves the others in theirs, one added comes last, one
//! moved keeps its place.
class HeldSystem {
 public:
  //! Steps between checks of the solution's drift: each adds rounding of the order of the
  //! system's condition number times machine epsilon. At a check the solution's residual is
  //! measured (|C|^2, as a step) and refined (refine_held_solution), and the set factored afresh
  //! (|C|^3, about |C| steps) only where the residual exceeds kDrift of its scale. On CGAL's
  //! cheese (about 640 cones, 1,000 steps) 32 steps left residuals of 2e-16 to 4e-15 after a
  //! factorization, whose 34 took 2.7 s of a placement of 15 s; refined at each check and never
  //! factored again, at most 5e-14 (7e-13 unrefined); on a 117k-face CAD head (353 cones) 4e-16.
  static constexpr int kStepsBetweenDriftChecks = 32;
  static constexpr double kDrift = 1e-12;
  //! `drift`: the residual, relative to the system's scale, above which the set is factored
  //! afresh at a check.
  explicit HeldSystem(LinearConeModel& model, double drift = kDrift)
      : model_(model), drift_(drift) {}
  //! Factors the set's system; false where it is singular (the set then has no solution).
  bool reset(const std::vector<int>& cones);
  bool valid() const { return valid_; }
  const std::vector<int>& cones() const { return cones_; }
  //! The sets factored so far (reset, and the steps that factored afresh).
  int factorizations() const { return factorizations_; }
  LinearConeModel::Solution solution() const;
  //! The set without its i-th cone: O(|C|) (and its D, O(|C|^2)).
  LinearConeModel::Solution without(int i) const;
  //! The set with v added last; with its i-th cone moved to v (moved = i). Solves v's column.
  LinearConeModel::Solution with(int v, int moved = -1);
  //! Changes the set as `with` and `without` solve it.
  void add(int v, int moved = -1);
  void remove(int i);

 private:
  // v's row r, column a and corner d bordering the system of the cones `base` (v's column solved).
  struct Border {
    Eigen::VectorXd a;
    Eigen::RowVectorXd r;
    double d = 0;
  };
  Border border(const std::vector<int>& base, int v);
  // The set `base` (solution x, B a: its inverse times the border's column) bordered by v, v's
  // entry moved to index `at` among the cones: its cones, solution, and what the inverse's
  // bordering needs.
  struct Grown {
    bool ok = false;
    std::vector<int> cones;
    Eigen::VectorXd x, ba;  // ba: B a
    Eigen::RowVectorXd r;
    double s = 0;
    std::vector<int> order;  // grown index -> bordered system's (base, then v)
  };
  Grown grow(const Eigen::VectorXd& x, const Eigen::VectorXd& ba, const Border& b,
             const std::vector<int>& base, int v, int at);
  // Whether the set stays regular without its i-th cone.
  bool droppable(int i) const;
  // The solution without index i, and the held inverse and solution made so (Schur complement).
  Eigen::VectorXd x_without(int i) const;
  void drop_index(int i);
  // The solution x of a step (of `cones` cones), with D from the held quadratic form: k's
  // entries of the set's cones at their indices (0 where one is left out) and v's, if added.
  LinearConeModel::Solution step_solution(long cones, const Eigen::VectorXd& x,
                                          const Eigen::VectorXd& k_held, int v, double k_v) const;
  // The quadratic form's rows, sums and sums with g of the set's cones, in their order.
  void reset_sums();
  // Whether the kept solution has drifted from the set's system (its residual); else it is
  // refined by a step of iterative refinement.
  bool drifted();
  // Every so many steps, whether the set is to be factored afresh (drifted).
  bool due_for_factorization();

  LinearConeModel& model_;
  double drift_;
  std::vector<int> cones_;
  Eigen::MatrixXd inverse_;  // of the bordered system (cones, then c on a closed surface)
  Eigen::VectorXd x_;        // its solution
  // The cones' area-weighted sums: gram_(i, j) = A col_i . col_j, sum_(i) = A . col_i,
  // with_g_(i) = A col_i . g: dense, so that a step's D is one matrix-vector product.
  Eigen::MatrixXd gram_;
  Eigen::VectorXd sum_, with_g_;
  bool valid_ = false;
  int updates_ = 0;  // since the last check of the drift
  int factorizations_ = 0;
};

}  // namespace ricci
