#include "ricci/compact_mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "mesh_checks.h"

namespace ricci {

using detail::fail;
using detail::first_indices;

CompactMesh::CompactMesh(std::vector<Eigen::Vector3d> positions,
                         std::vector<std::array<int, 3>> faces)
    : positions_(std::move(positions)) {
  faces_ = std::move(faces);
  check_elements();
  build_connectivity(static_cast<int>(positions_.size()));
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
  std::map<std::array<int, 3>, int> seen;
  std::vector<int> duplicates;
  for (int f = 0; f < num_faces(); ++f) {
    std::array<int, 3> key = faces_[f];
    std::sort(key.begin(), key.end());
    auto [it, inserted] = seen.emplace(key, f);
    if (!inserted) duplicates.push_back(f);
  }
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
