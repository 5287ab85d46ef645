#include "ricci/mesh/compact_mesh.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "mesh/mesh_checks.h"

namespace ricci {

using detail::fail;
using detail::first_indices;
using detail::repeated_triangles;

CompactMesh::CompactMesh(std::vector<Eigen::Vector3d> positions,
                         std::vector<std::array<int, 3>> faces)
    : positions_(std::move(positions)) {
  faces_ = std::move(faces);
  check_elements();
  build_connectivity(static_cast<int>(positions_.size()));
  measure_input_lengths();
}

CompactMesh CompactMesh::doubled(const CompactMesh& mesh) {
  const int n = mesh.num_vertices(), nf = mesh.num_faces();
  CompactMesh d;
  d.positions_ = mesh.positions_;
  std::vector<int> copy(n);
  for (int v = 0; v < n; ++v) {
    if (mesh.is_boundary_vertex(v)) {
      copy[v] = v;
    } else {
      copy[v] = static_cast<int>(d.positions_.size());
      d.positions_.push_back(mesh.positions_[v]);
    }
  }
  const int nd = static_cast<int>(d.positions_.size());
  d.faces_ = mesh.faces_;
  d.faces_.reserve(2 * nf);
  for (int f = 0; f < nf; ++f) {
    const auto& t = mesh.faces_[f];
    d.faces_.push_back({copy[t[0]], copy[t[2]], copy[t[1]]});
  }
  // Halfedges pair by their vertices, except that a mirrored halfedge which is not a boundary
  // edge of the mesh names its boundary vertices by keys of their own: an interior edge between
  // two boundary vertices then has a copy of its own instead of meeting its original.
  std::vector<std::array<int, 2>> keys(3 * d.faces_.size());
  for (int h = 0; h < 3 * nf; ++h) keys[h] = {mesh.halfedge_tail(h), mesh.halfedge_head(h)};
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      // Mirrored face (t0, t2, t1): the edge opposite its corner c is the original's opposite
      // corner (3 - c) % 3, reversed.
      const int original = 3 * f + (3 - c) % 3;
      const bool seam = mesh.twin(original) < 0;
      std::array<int, 2> k;
      for (int end = 0; end < 2; ++end) {
        const int v = end == 0 ? mesh.halfedge_head(original) : mesh.halfedge_tail(original);
        k[end] = !seam && mesh.is_boundary_vertex(v) ? nd + v : copy[v];
      }
      keys[3 * (nf + f) + c] = k;
    }
  }
  d.build_connectivity(nd, keys, nd + n);
  d.measure_input_lengths();
  return d;
}

void CompactMesh::measure_input_lengths() {
  input_lengths_.resize(num_edges());
  for (int e = 0; e < num_edges(); ++e) {
    input_lengths_[e] =
        (positions_[edge_vertices_[e][0]] - positions_[edge_vertices_[e][1]]).norm();
  }
}

void CompactMesh::check_elements() {
  const int n = static_cast<int>(positions_.size());
  if (n == 0 || faces_.empty()) {
    throw InvalidMeshError("mesh: it has " + std::to_string(n) + " vertices and " +
                           std::to_string(faces_.size()) +
                           " faces; the flow needs a triangle mesh with at least one face");
  }
  std::vector<int> bad;
  for (int v = 0; v < n; ++v) {
    if (!positions_[v].allFinite()) bad.push_back(v);
  }
  if (!bad.empty()) {
    fail(std::to_string(bad.size()) + " vertices have NaN or infinite coordinates",
         first_indices("vertex", bad), "remove or repair them before running the flow");
  }
  for (int f = 0; f < num_faces(); ++f) {
    for (int v : faces_[f]) {
      if (v < 0 || v >= n) bad.push_back(f);
    }
  }
  if (!bad.empty()) {
    fail(std::to_string(bad.size()) + " faces reference vertices that do not exist",
         first_indices("face", bad), "the file is corrupt; re-export it");
  }
  std::vector<int> degenerate;
  for (int f = 0; f < num_faces(); ++f) {
    const auto& t = faces_[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      degenerate.push_back(f);
      continue;
    }
    const Eigen::Vector3d& p0 = positions_[t[0]];
    const Eigen::Vector3d e1 = positions_[t[1]] - p0, e2 = positions_[t[2]] - p0;
    const double longest = std::max(
        {e1.squaredNorm(), e2.squaredNorm(), (positions_[t[2]] - positions_[t[1]]).squaredNorm()});
    // Twice the area against the longest edle squared: 0 for collinear corners.
    if (!(e1.cross(e2).norm() > 1e-12 * longest)) degenerate.push_back(f);
  }
  if (!degenerate.empty()) {
    fail(std::to_string(degenerate.size()) + " degenerate faces (zero area or repeated vertex)",
         first_indices("face", degenerate),
         "remove them, e.g. MeshLab's Filters > Cleaning and Repairing > Remove Zero Area Faces");
  }
  std::vector<char> referenced(n, 0);
  for (const auto& t : faces_) {
    for (int v : t) referenced[v] = 1;
  }
  for (int v = 0; v < n; ++v) {
    if (!referenced[v]) bad.push_back(v);
  }
  if (!bad.empty()) {
    fail(std::to_string(bad.size()) + " unreferenced vertices", first_indices("vertex", bad),
         "remove them, e.g. MeshLab's Filters > Cleaning and Repairing > Remove Unreferenced "
         "Vertices");
  }
  const std::vector<int> duplicates =
      repeated_triangles(n, num_faces(), [&](int f) { return faces_[f]; });
  if (!duplicates.empty()) {
    fail(std::to_string(duplicates.size()) + " duplicate faces (same three vertices as another)",
         first_indices("face", duplicates),
         "remove them, e.g. MeshLab's Filters > Cleaning and Repairing > Remove Duplicate Faces");
  }
}

double CompactMesh::input_area() const {
  double area = 0;
  for (const auto& t : faces_) {
    area += 0.5 *
            (positions_[t[1]] - positions_[t[0]]).cross(positions_[t[2]] - positions_[t[0]]).norm();
  }
  return area;
}

}  // namespace ricci
