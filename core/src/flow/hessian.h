// The Hessian H = dK/du of the Ricci energy as a sparse symmetric matrix over the free
// vertices, assembled face by face as -(d theta/d l)(d l/d u) (DESIGN.md, section 1).
#pragma once

#include <array>
#include <vector>

#include <Eigen/SparseCore>

#include "flow/metric.h"
#include "ricci/mesh/triangulation.h"

namespace ricci {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

//! d theta / d u of one face: [corner][corner], symmetric (paper, Lemma "Symmetry").
std::array<std::array<double, 3>, 3> face_angle_jacobian(const Triangulation& mesh,
                                                         const MetricState& state, int f);

//! Builds the sparsity pattern once per connectivity; assemble() then only writes values.
class HessianAssembler {
 public:
  //! free_index[v] is the row of vertex v, or -1 where u is held fixed.
  HessianAssembler(const Triangulation& mesh, std::vector<int> free_index);

  //! H restricted to the free vertices (both triangles stored). \pre state.valid()
  const SparseMatrix& assemble(const MetricState& state);

  //! The last assembled H.
  const SparseMatrix& matrix() const { return matrix_; }
  int num_free() const { return static_cast<int>(matrix_.rows()); }

 private:
  const Triangulation& mesh_;
  std::vector<int> free_index_;
  SparseMatrix matrix_;
  std::vector<std::array<int, 9>> slots_;  //!< per face, value index of (row corner, col corner)
};

//! H^2 (S2's Levenberg-Marquardt matrix) into `square`, without the temporaries of Eigen's
//! product (in the same summation order): with keep_pattern, `square` already holds H^2's pattern
//! from an earlier H of the same pattern (checked only by size), and only its values are written.
void square_symmetric(const SparseMatrix& h, SparseMatrix& square, bool keep_pattern);

}  // namespace ricci
