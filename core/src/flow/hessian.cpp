#include "flow/hessian.h"

#include <algorithm>

namespace ricci {

std::array<std::array<double, 3>, 3> face_angle_jacobian(const Triangulation& mesh,
                                                         const MetricState& state, int f) {
  // d l_k / d u at each corner: edge k is opposite corner k and joins corners k+1 and k+2.
  double dl_du[3][3] = {};  // [edge k][corner]
  for (int k = 0; k < 3; ++k) {
    const int e = mesh.face_edge(f, k);
    const EdgeLength& el = state.edges[e];
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    const bool a_first = mesh.face_vertex(f, a) == mesh.edge_vertices(e)[0];
    dl_du[k][a] = a_first ? el.d_ui : el.d_uj;
    dl_du[k][b] = a_first ? el.d_uj : el.d_ui;
  }
  const auto& dtheta_dl = state.faces[f].d_angle_d_length;
  std::array<std::array<double, 3>, 3> j{};
  for (int c = 0; c < 3; ++c) {
    for (int w = 0; w < 3; ++w) {
      double sum = 0;
      for (int k = 0; k < 3; ++k) sum += dtheta_dl[c][k] * dl_du[k][w];
      j[c][w] = sum;
    }
  }
  return j;
}

HessianAssembler::HessianAssembler(const Triangulation& mesh, std::vector<int> free_index)
    : mesh_(mesh), free_index_(std::move(free_index)) {
  const int n = static_cast<int>(
      std::count_if(free_index_.begin(), free_index_.end(), [](int i) { return i >= 0; }));
  // The pattern in compressed columns directly (it is rebuilt at every change of connectivity,
  // dozens of times in a flow with flips): each face's (row, column) pairs bucketed by column,
  // then each column's rows sorted and made unique (every face at a vertex gives its diagonal
  // entry, both faces of an edge give its pair).
  std::vector<int> start(n + 1, 0);
  const auto rows_of_face = [&](int f, auto&& visit) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        const int r = free_index_[mesh.face_vertex(f, a)], c = free_index_[mesh.face_vertex(f, b)];
        if (r >= 0 && c >= 0) visit(r, c);
      }
    }
  };
  for (int f = 0; f < mesh.num_faces(); ++f) rows_of_face(f, [&](int, int c) { ++start[c + 1]; });
  for (int c = 0; c < n; ++c) start[c + 1] += start[c];
  std::vector<int> rows(static_cast<size_t>(start[n])), fill(start.begin(), start.end() - 1);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    rows_of_face(f, [&](int r, int c) { rows[fill[c]++] = r; });
  }
  matrix_.resize(n, n);
  std::vector<int> outer(n + 1, 0);
  int kept = 0;
  for (int c = 0; c < n; ++c) {
    const auto first = rows.begin() + start[c], last = rows.begin() + start[c + 1];
    std::sort(first, last);
    const auto unique_end = std::unique(first, last);
    for (auto r = first; r != unique_end; ++r) rows[kept++] = *r;
    outer[c + 1] = kept;
  }
  matrix_.resizeNonZeros(kept);
  std::copy(outer.begin(), outer.end(), matrix_.outerIndexPtr());
  std::copy(rows.begin(), rows.begin() + kept, matrix_.innerIndexPtr());
  std::fill(matrix_.valuePtr(), matrix_.valuePtr() + kept, 0.0);
  slots_.assign(mesh.num_faces(), {});
  const int* inner = matrix_.innerIndexPtr();
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        const int r = free_index_[mesh.face_vertex(f, a)], c = free_index_[mesh.face_vertex(f, b)];
        int slot = -1;
        if (r >= 0 && c >= 0) {
          const int* found = std::lower_bound(inner + outer[c], inner + outer[c + 1], r);
          slot = static_cast<int>(found - inner);
        }
        slots_[f][3 * a + b] = slot;
      }
    }
  }
}

const SparseMatrix& HessianAssembler::assemble(const MetricState& state) {
  double* values = matrix_.valuePtr();
  std::fill(values, values + matrix_.nonZeros(), 0.0);
  for (int f = 0; f < mesh_.num_faces(); ++f) {
    const auto j = face_angle_jacobian(mesh_, state, f);
    const auto& slot = slots_[f];
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        // K = 2 pi - sum theta, so dK/du = -d theta/d u; symmetrized against round-off.
        if (slot[3 * a + b] >= 0) values[slot[3 * a + b]] -= 0.5 * (j[a][b] + j[b][a]);
      }
    }
  }
  return matrix_;
}

void square_symmetric(const SparseMatrix& h, SparseMatrix& square, bool keep_pattern) {
  const int n = static_cast<int>(h.rows());
  const int* outer = h.outerIndexPtr();
  const int* inner = h.innerIndexPtr();
  const double* value = h.valuePtr();
  if (!keep_pattern || square.rows() != n) {
    // Column j of H^2 has an entry in every row i two edges from j or closer.
    std::vector<int> columns(n + 1, 0), rows, seen(n, -1);
    rows.reserve(static_cast<size_t>(4 * h.nonZeros()));
    for (int j = 0; j < n; ++j) {
      const size_t first = rows.size();
      for (int a = outer[j]; a < outer[j + 1]; ++a) {
        for (int b = outer[inner[a]]; b < outer[inner[a] + 1]; ++b) {
          if (seen[inner[b]] != j) seen[inner[b]] = j, rows.push_back(inner[b]);
        }
      }
      std::sort(rows.begin() + static_cast<long>(first), rows.end());
      columns[j + 1] = static_cast<int>(rows.size());
    }
    square = SparseMatrix(n, n);
    square.resizeNonZeros(static_cast<long>(rows.size()));
    std::copy(columns.begin(), columns.end(), square.outerIndexPtr());
    std::copy(rows.begin(), rows.end(), square.innerIndexPtr());
  }
  // (H^2)(:, j) = sum over k of H(:, k) H(k, j), gathered in a dense column.
  std::vector<double> column(n, 0.0);
  const int* square_outer = square.outerIndexPtr();
  const int* square_inner = square.innerIndexPtr();
  double* square_value = square.valuePtr();
  for (int j = 0; j < n; ++j) {
    for (int a = outer[j]; a < outer[j + 1]; ++a) {
      const int k = inner[a];
      for (int b = outer[k]; b < outer[k + 1]; ++b) column[inner[b]] += value[b] * value[a];
    }
    for (int c = square_outer[j]; c < square_outer[j + 1]; ++c) {
      square_value[c] = column[square_inner[c]];
      column[square_inner[c]] = 0;
    }
  }
}

}  // namespace ricci
