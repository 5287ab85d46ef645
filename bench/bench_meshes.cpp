#include "bench_meshes.h"

#include <map>
#include <memory>

#include "ricci/mesh_io.h"

namespace ricci::bench {

CompactMesh subdivide_midpoint(const CompactMesh& mesh, int levels) {
  std::vector<Eigen::Vector3d> p = mesh.positions();
  std::vector<std::array<int, 3>> f = mesh.faces();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int i, int j) {
      const std::pair<int, int> key(std::min(i, j), std::max(i, j));
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      p.push_back(0.5 * (p[i] + p[j]));
      return midpoint[key] = static_cast<int>(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> g;
    g.reserve(4 * f.size());
    for (const auto& t : f) {
      const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      g.push_back({t[0], ab, ca});
      g.push_back({t[1], bc, ab});
      g.push_back({t[2], ca, bc});
      g.push_back({ab, bc, ca});
    }
    f = std::move(g);
  }
  return CompactMesh(std::move(p), std::move(f));
}

const CompactMesh& lion_head(int levels) {
  static std::map<int, std::unique_ptr<CompactMesh>> cache;
  auto& slot = cache[levels];
  if (!slot) {
    VcgMesh m;
    read_mesh(std::string(RICCI_CGAL_DATA_DIR) + "/lion-head.off", m);
    slot = std::make_unique<CompactMesh>(subdivide_midpoint(compact_mesh_from_vcg(m), levels));
  }
  return *slot;
}

}  // namespace ricci::bench
