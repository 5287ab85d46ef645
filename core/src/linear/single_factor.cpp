#include "linear/single_factor.h"

#include <algorithm>
#include <numeric>
#include <thread>

namespace ricci::detail {

namespace {

// Each subtree solved on its own thread holds at least this share of the factor's entries.
constexpr double kSmallestShare = 0.2;

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

SinglePrecisionFactor::SinglePrecisionFactor(const cholmod_factor& factor,
                                             std::size_t two_threads_from)
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
  for (int q = 0; q < nsuper; ++q) max_rows_ = std::max(max_rows_, pi[q + 1] - pi[q]);
  choose_subtrees(two_threads_from);
}

// The supernodal elimination tree: a supernode's parent holds the first row below its columns.
// CHOLMOD numbers supernodes in postorder, so a subtree is the range from its first descendant to
// its root. From the root down through single children to the first node with several: that node
// and its ancestors are the top; its children's subtrees, independent of each other, go to two
// threads, the largest first to the one with less work, when each thread gets enough.
void SinglePrecisionFactor::choose_subtrees(std::size_t two_threads_from) {
  const int nsuper = static_cast<int>(first_column_.size()) - 1;
  top_ = {0, nsuper};
  if (values_.size() < two_threads_from) return;
  std::vector<int> first_descendant(nsuper);
  std::iota(first_descendant.begin(), first_descendant.end(), 0);
  std::vector<std::size_t> work(nsuper, 0);            // entries in the subtree
  std::vector<std::vector<int>> children(nsuper + 1);  // nsuper: the roots
  for (int q = 0; q < nsuper; ++q) {
    const int ncols = first_column_[q + 1] - first_column_[q];
    const int nrows = row_start_[q + 1] - row_start_[q];
    work[q] += static_cast<std::size_t>(ncols) * nrows;
    int parent = nsuper;
    if (nrows > ncols) {
      const int row = rows_[row_start_[q] + ncols];
      parent = static_cast<int>(std::upper_bound(first_column_.begin(), first_column_.end(), row) -
                                first_column_.begin() - 1);
      work[parent] += work[q];
      first_descendant[parent] = std::min(first_descendant[parent], first_descendant[q]);
    }
    children[parent].push_back(q);
  }
  int node = nsuper;
  while (children[node].size() == 1) node = children[node][0];
  std::vector<int> kids = children[node];
  std::sort(kids.begin(), kids.end(), [&](int a, int b) { return work[a] > work[b]; });
  std::size_t load[2] = {0, 0};
  std::vector<Range> parts[2];
  for (int kid : kids) {
    const int lighter = load[1] < load[0];
    load[lighter] += work[kid];
    parts[lighter].push_back({first_descendant[kid], kid + 1});
  }
  if (static_cast<double>(std::min(load[0], load[1])) <
      kSmallestShare * static_cast<double>(values_.size())) {
    return;
  }
  subtrees_[0] = std::move(parts[0]);
  subtrees_[1] = std::move(parts[1]);
  top_ = {node, nsuper};
}

// Each supernode is a dense block of nrows x ncols, column-major: its columns' rows first (the
// lower triangle), then the rows below. Its entries of y are gathered once, so the inner loops
// read the block and nothing else.
void SinglePrecisionFactor::forward(Range range, double* y, double* ancestors, int ancestors_from,
                                    std::vector<double>& local) const {
  for (int q = range.begin; q < range.end; ++q) {
    const int ncols = first_column_[q + 1] - first_column_[q];
    const int nrows = row_start_[q + 1] - row_start_[q];
    const int* rows = rows_.data() + row_start_[q];
    const float* block = values_.data() + value_start_[q];
    local.resize(nrows);
    for (int i = 0; i < nrows; ++i) local[i] = rows[i] < ancestors_from ? y[rows[i]] : 0.0;
    for (int j = 0; j < ncols; ++j) {
      const float* column = block + static_cast<std::size_t>(j) * nrows;
      const double t = local[j] / column[j];
      local[j] = t;
      for (int i = j + 1; i < nrows; ++i) local[i] -= column[i] * t;
    }
    for (int i = 0; i < nrows; ++i) {
      if (rows[i] < ancestors_from) {
        y[rows[i]] = local[i];
      } else {
        ancestors[rows[i] - ancestors_from] += local[i];
      }
    }
  }
}

void SinglePrecisionFactor::backward(Range range, double* x, std::vector<double>& local) const {
  for (int q = range.end - 1; q >= range.begin; --q) {
    const int ncols = first_column_[q + 1] - first_column_[q];
    const int nrows = row_start_[q + 1] - row_start_[q];
    const int* rows = rows_.data() + row_start_[q];
    const float* block = values_.data() + value_start_[q];
    local.resize(nrows);
    for (int i = 0; i < nrows; ++i) local[i] = x[rows[i]];
    for (int j = ncols - 1; j >= 0; --j) {
      const float* column = block + static_cast<std::size_t>(j) * nrows;
      local[j] = (local[j] - dot(column, local.data(), j + 1, nrows)) / column[j];
    }
    for (int j = 0; j < ncols; ++j) x[first_column_[q] + j] = local[j];
  }
}

Eigen::VectorXd SinglePrecisionFactor::solve(const Eigen::VectorXd& b) const {
  Eigen::VectorXd z(n_);
  for (int k = 0; k < n_; ++k) z[k] = b[perm_[k]];
  std::vector<double> local, other_local;  // sized here: the other thread allocates nothing
  local.reserve(max_rows_);
  if (subtrees_[0].empty()) {
    forward(top_, z.data(), nullptr, n_, local);
    backward(top_, z.data(), local);
  } else {
    // A subtree's rows outside its own columns are the top's: each thread adds its updates there
    // into an array of its own, and the two are added in a fixed order.
    const int from = first_column_[top_.begin];
    std::vector<double> ancestors[2] = {std::vector<double>(n_ - from, 0.0),
                                        std::vector<double>(n_ - from, 0.0)};
    other_local.reserve(max_rows_);
    std::thread other([&] {
      for (const Range& r : subtrees_[1])
        forward(r, z.data(), ancestors[1].data(), from, other_local);
    });
    for (const Range& r : subtrees_[0]) forward(r, z.data(), ancestors[0].data(), from, local);
    other.join();
    for (int k = from; k < n_; ++k) z[k] += ancestors[0][k - from] + ancestors[1][k - from];
    forward(top_, z.data(), nullptr, n_, local);
    backward(top_, z.data(), local);
    std::thread other_back([&] {
      for (const Range& r : subtrees_[1]) backward(r, z.data(), other_local);
    });
    for (const Range& r : subtrees_[0]) backward(r, z.data(), local);
    other_back.join();
  }
  Eigen::VectorXd out(n_);
  for (int k = 0; k < n_; ++k) out[perm_[k]] = z[k];
  return out;
}

}  // namespace ricci::detail
