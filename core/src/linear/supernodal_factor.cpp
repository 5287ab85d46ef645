#include "linear/supernodal_factor.h"

#include <algorithm>
#include <numeric>
#include <type_traits>

#include "mesh/two_threads.h"

namespace ricci::detail {

namespace {

// Each subtree solved on its own thread holds at least this share of the factor's entries.
constexpr double kSmallestShare = 0.2;

// sum of column[i] * x[i] over [begin, end), in four interleaved sums (in a fixed order) that the
// compiler can keep in vector registers.
template <class Value>
double dot(const Value* column, const double* x, int begin, int end) {
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

template <class Value>
SupernodalFactor<Value>::SupernodalFactor(const cholmod_factor& factor,
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
  inverse_perm_.resize(n_);
  for (int k = 0; k < n_; ++k) inverse_perm_[perm_[k]] = k;
  if constexpr (std::is_same_v<Value, double>) {
    values_ = x;
  } else {
    own_.assign(x, x + factor.xsize);
    values_ = own_.data();
  }
  // A supernode's parent holds the first row below its columns.
  parent_.assign(nsuper, -1);
  supernode_of_.resize(n_);
  for (int q = 0; q < nsuper; ++q) {
    const int ncols = first_column_[q + 1] - first_column_[q];
    const int nrows = row_start_[q + 1] - row_start_[q];
    max_rows_ = std::max(max_rows_, nrows);
    std::fill(supernode_of_.begin() + first_column_[q],
              supernode_of_.begin() + first_column_[q + 1], q);
    if (nrows > ncols) {
      const int row = rows_[row_start_[q] + ncols];
      parent_[q] =
          static_cast<int>(std::upper_bound(first_column_.begin(), first_column_.end(), row) -
                           first_column_.begin() - 1);
    }
  }
  choose_subtrees(two_threads_from);
}

// CHOLMOD numbers supernodes in postorder, so a subtree is the range from its first descendant to
// its root. From the root down through single children to the first node with several: that node
// and its ancestors are the top; its children's subtrees, independent of each other, go to two
// threads, the largest first to the one with less work, when each thread gets enough.
template <class Value>
void SupernodalFactor<Value>::choose_subtrees(std::size_t two_threads_from) {
  const int nsuper = static_cast<int>(first_column_.size()) - 1;
  top_ = {0, nsuper};
  const std::size_t entries = value_start_.back();
  if (entries < two_threads_from) return;
  std::vector<int> first_descendant(nsuper);
  std::iota(first_descendant.begin(), first_descendant.end(), 0);
  std::vector<std::size_t> work(nsuper, 0);            // entries in the subtree
  std::vector<std::vector<int>> children(nsuper + 1);  // nsuper: the roots
  for (int q = 0; q < nsuper; ++q) {
    work[q] += value_start_[q + 1] - value_start_[q];
    const int parent = parent_[q] < 0 ? nsuper : parent_[q];
    if (parent < nsuper) {
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
      kSmallestShare * static_cast<double>(entries)) {
    return;
  }
  subtrees_[0] = std::move(parts[0]);
  subtrees_[1] = std::move(parts[1]);
  top_ = {node, nsuper};
}

// Each supernode is a dense block of nrows x ncols, column-major: its columns' rows first (the
// lower triangle), then the rows below. Its entries of y are gathered once, so the inner loops
// read the block and nothing else.
template <class Value>
void SupernodalFactor<Value>::forward(int q, double* y, double* ancestors, int ancestors_from,
                                      std::vector<double>& local) const {
  const int ncols = first_column_[q + 1] - first_column_[q];
  const int nrows = row_start_[q + 1] - row_start_[q];
  const int* rows = rows_.data() + row_start_[q];
  const Value* block = values_ + value_start_[q];
  local.resize(nrows);
  for (int i = 0; i < nrows; ++i) local[i] = rows[i] < ancestors_from ? y[rows[i]] : 0.0;
  for (int j = 0; j < ncols; ++j) {
    const Value* column = block + static_cast<std::size_t>(j) * nrows;
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

template <class Value>
void SupernodalFactor<Value>::forward(Range range, double* y, double* ancestors, int ancestors_from,
                                      std::vector<double>& local) const {
  for (int q = range.begin; q < range.end; ++q) forward(q, y, ancestors, ancestors_from, local);
}

template <class Value>
void SupernodalFactor<Value>::backward(Range range, double* x, int count,
                                       std::vector<double>& local) const {
  for (int q = range.end - 1; q >= range.begin; --q) {
    const int ncols = first_column_[q + 1] - first_column_[q];
    const int nrows = row_start_[q + 1] - row_start_[q];
    const int* rows = rows_.data() + row_start_[q];
    const Value* block = values_ + value_start_[q];
    local.resize(static_cast<std::size_t>(nrows) * count);
    for (int c = 0; c < count; ++c) {
      const double* xc = x + static_cast<std::size_t>(c) * n_;
      double* lc = local.data() + static_cast<std::size_t>(c) * nrows;
      for (int i = 0; i < nrows; ++i) lc[i] = xc[rows[i]];
    }
    for (int j = ncols - 1; j >= 0; --j) {
      const Value* column = block + static_cast<std::size_t>(j) * nrows;
      for (int c = 0; c < count; ++c) {
        double* lc = local.data() + static_cast<std::size_t>(c) * nrows;
        lc[j] = (lc[j] - dot(column, lc, j + 1, nrows)) / column[j];
      }
    }
    for (int c = 0; c < count; ++c) {
      double* xc = x + static_cast<std::size_t>(c) * n_;
      const double* lc = local.data() + static_cast<std::size_t>(c) * nrows;
      for (int j = 0; j < ncols; ++j) xc[first_column_[q] + j] = lc[j];
    }
  }
}

template <class Value>
void SupernodalFactor<Value>::backward(double* x, int count) const {
  std::vector<double> local;
  local.reserve(static_cast<std::size_t>(max_rows_) * count);
  backward(top_, x, count, local);
  if (subtrees_[0].empty()) return;
  std::vector<double> other_local;  // sized here: the other thread allocates nothing
  other_local.reserve(static_cast<std::size_t>(max_rows_) * count);
  detail::both(
      [&] {
        for (const Range& r : subtrees_[0]) backward(r, x, count, local);
      },
      [&] {
        for (const Range& r : subtrees_[1]) backward(r, x, count, other_local);
      },
      true);
}

template <class Value>
Eigen::VectorXd SupernodalFactor<Value>::solve(const Eigen::VectorXd& b) const {
  Eigen::VectorXd z(n_);
  for (int k = 0; k < n_; ++k) z[k] = b[perm_[k]];
  std::vector<double> local;
  local.reserve(max_rows_);
  if (subtrees_[0].empty()) {
    forward(top_, z.data(), nullptr, n_, local);
  } else {
    // A subtree's rows outside its own columns are the top's: each thread adds its updates there
    // into an array of its own, and the two are added in a fixed order.
    const int from = first_column_[top_.begin];
    std::vector<double> ancestors[2] = {std::vector<double>(n_ - from, 0.0),
                                        std::vector<double>(n_ - from, 0.0)};
    std::vector<double> other_local;  // sized here: the other thread allocates nothing
    other_local.reserve(max_rows_);
    detail::both(
        [&] {
          for (const Range& r : subtrees_[0])
            forward(r, z.data(), ancestors[0].data(), from, local);
        },
        [&] {
          for (const Range& r : subtrees_[1])
            forward(r, z.data(), ancestors[1].data(), from, other_local);
        },
        true);
    for (int k = from; k < n_; ++k) z[k] += ancestors[0][k - from] + ancestors[1][k - from];
    forward(top_, z.data(), nullptr, n_, local);
  }
  backward(z.data(), 1);
  Eigen::VectorXd out(n_);
  for (int k = 0; k < n_; ++k) out[perm_[k]] = z[k];
  return out;
}

// A column's forward solve changes only the entries of the supernodes its nonzero rows reach: the
// paths from theirs to the root, in postorder (ascending) as the full solve takes them.
template <class Value>
Eigen::MatrixXd SupernodalFactor<Value>::solve_sparse(const Eigen::SparseMatrix<double>& b) const {
  const int count = static_cast<int>(b.cols());
  Eigen::MatrixXd z = Eigen::MatrixXd::Zero(n_, count);
  std::vector<char> reached(parent_.size(), 0);
  std::vector<int> path;
  std::vector<double> local;
  local.reserve(max_rows_);
  for (int c = 0; c < count; ++c) {
    path.clear();
    for (Eigen::SparseMatrix<double>::InnerIterator it(b, c); it; ++it) {
      const int k = inverse_perm_[it.row()];
      z(k, c) = it.value();
      for (int q = supernode_of_[k]; q >= 0 && !reached[q]; q = parent_[q]) {
        reached[q] = 1;
        path.push_back(q);
      }
    }
    std::sort(path.begin(), path.end());
    for (int q : path) {
      forward(q, z.col(c).data(), nullptr, n_, local);
      reached[q] = 0;
    }
  }
  backward(z.data(), count);
  Eigen::MatrixXd out(n_, count);
  for (int k = 0; k < n_; ++k) out.row(perm_[k]) = z.row(k);
  return out;
}

template <class Value>
std::size_t SupernodalFactor<Value>::entries_reached(int row) const {
  std::size_t entries = 0;
  for (int q = supernode_of_[inverse_perm_[row]]; q >= 0; q = parent_[q]) {
    entries += value_start_[q + 1] - value_start_[q];
  }
  return entries;
}

template class SupernodalFactor<float>;
template class SupernodalFactor<double>;

}  // namespace ricci::detail
