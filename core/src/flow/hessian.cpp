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
  // dozens of times in a flow with flips): column c has its diagonal and a row per edge at c's
  // vertex (loops and parallel edges of an intrinsic triangulation give one entry), each column
  // sorted and made unique; then each edge's two entries and each face's nine are looked up.
  const int num_edges = mesh.num_edges();
  const auto free_ends = [&](int e) {
    const auto [a, b] = mesh.edge_vertices(e);
    return std::array<int, 2>{free_index_[a], free_index_[b]};
  };
  std::vector<char> in_face(n, 0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int i = free_index_[mesh.face_vertex(f, c)];
      if (i >= 0) in_face[i] = 1;
    }
  }
  std::vector<int> start(n + 1, 0);
  for (int c = 0; c < n; ++c) start[c + 1] = in_face[c];
  for (int e = 0; e < num_edges; ++e) {
    const auto [i, j] = free_ends(e);
    if (i >= 0 && j >= 0) ++start[i + 1], ++start[j + 1];
  }
  for (int c = 0; c < n; ++c) start[c + 1] += start[c];
  std::vector<int> rows(static_cast<size_t>(start[n])), fill(start.begin(), start.end() - 1);
  for (int c = 0; c < n; ++c) {
    if (in_face[c]) rows[fill[c]++] = c;
  }
  for (int e = 0; e < num_edges; ++e) {
    const auto [i, j] = free_ends(e);
    if (i >= 0 && j >= 0) rows[fill[i]++] = j, rows[fill[j]++] = i;
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
  const int* inner = matrix_.innerIndexPtr();
  const auto slot_of = [&](int r, int c) {
    return static_cast<int>(std::lower_bound(inner + outer[c], inner + outer[c + 1], r) - inner);
  };
  // Per edge: the entry of its first vertex's row in its second vertex's column, and the other.
  std::vector<std::array<int, 2>> edge_slots(num_edges, {-1, -1});
  for (int e = 0; e < num_edges; ++e) {
    const auto [i, j] = free_ends(e);
    if (i >= 0 && j >= 0) edge_slots[e] = {slot_of(i, j), slot_of(j, i)};
  }
  slots_.assign(mesh.num_faces(), {});
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        int slot = -1;
        const int r = free_index_[mesh.face_vertex(f, a)], c = free_index_[mesh.face_vertex(f, b)];
        if (r >= 0 && c >= 0) {
          if (a == b) {
            slot = slot_of(c, c);
          } else {
            const int e = mesh.face_edge(f, 3 - a - b);  // the side from corner a to corner b
            slot = edge_slots[e][mesh.face_vertex(f, b) == mesh.edge_vertices(e)[1] ? 0 : 1];
          }
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
