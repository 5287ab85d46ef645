#include "single_factor.h"

#include <algorithm>

namespace ricci::detail {

SinglePrecisionFactor::SinglePrecisionFactor(const cholmod_factor& factor)
    : n_(static_cast<int>(factor.n)) {
  const int nsuper = static_cast<int>(factor.nsuper);
  const auto* super = static_cast<const int*>(factor.super);
  const auto* pi = static_cast<const int*>(factor.pi);
  const auto* px = static_cast<const int*>(factor.px);
  const auto* s = static_cast<const int*>(factor.s);
  const auto* perm = static_cast<const int*>(factor.Perm);
  const auto* x = static_cast<const double*>(factor.x);
  first_column_.assign(super, super + nsuper + 1);
  row_start_.assign(pi, pi + nsuper + 1);
  value_start_.assign(px, px + nsuper + 1);
  rows_.assign(s, s + row_start_.back());
  perm_.assign(perm, perm + n_);
  values_.assign(x, x + factor.xsize);
}

namespace {

// sum of column[i] * x[i] over [begin, end), in four interleaved sums (in a fixed order) that the
// compiler can keep in vector registers.
double dot(const float* column, const double* x, int begin, int end) {
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  int i = begin;
  for (; i + 4 <= end; i += 4) {
    s0 += column[i] * x[i];
    s1 += column[i + 1] * x[i + 1];
    s2 += column[i + 2] * x[i + 2];
    s3 += column[i + 3] * x[i + 3];
  }
  for (; i < end; ++i) s0 += column[i] * x[i];
  return (s0 + s1) + (s2 + s3);
}

}  // namespace

Eigen::VectorXd SinglePrecisionFactor::solve(const Eigen::VectorXd& b) const {
  Eigen::VectorXd z(n_);
  for (int k = 0; k < n_; ++k) z[k] = b[perm_[k]];
  // Each supernode is a dense block of nrows x ncols, column-major: its columns' rows first (the
  // lower triangle), then the rows below. Its entries of z are gathered once, so the inner loops
  // read the block and nothing else.
  std::vector<double> local;
  const int nsuper = static_cast<int>(first_column_.size()) - 1;
  for (int q = 0; q < nsuper; ++q) {  // L y = P b
    const int ncols = first_column_[q + 1] - first_column_[q];
    const int nrows = row_start_[q + 1] - row_start_[q];
    const int* rows = rows_.data() + row_start_[q];
    const float* block = values_.data() + value_start_[q];
    local.resize(nrows);
    for (int i = 0; i < nrows; ++i) local[i] = z[rows[i]];
    for (int j = 0; j < ncols; ++j) {
      const float* column = block + static_cast<std::size_t>(j) * nrows;
      const double t = local[j] / column[j];
      local[j] = t;
      for (int i = j + 1; i < nrows; ++i) local[i] -= column[i] * t;
    }
    for (int i = 0; i < nrows; ++i) z[rows[i]] = local[i];
  }
  for (int q = nsuper - 1; q >= 0; --q) {  // L^T x = y
    const int ncols = first_column_[q + 1] - first_column_[q];
    const int nrows = row_start_[q + 1] - row_start_[q];
    const int* rows = rows_.data() + row_start_[q];
    const float* block = values_.data() + value_start_[q];
    local.resize(nrows);
    for (int i = 0; i < nrows; ++i) local[i] = z[rows[i]];
    for (int j = ncols - 1; j >= 0; --j) {
      const float* column = block + static_cast<std::size_t>(j) * nrows;
      local[j] = (local[j] - dot(column, local.data(), j + 1, nrows)) / column[j];
    }
    for (int j = 0; j < ncols; ++j) z[first_column_[q] + j] = local[j];
  }
  Eigen::VectorXd out(n_);
  for (int k = 0; k < n_; ++k) out[perm_[k]] = z[k];
  return out;
}

}  // namespace ricci::detail
