#include "bench_meshes.h"

#include <map>
#include <memory>

#include "test_meshes.h"

namespace ricci::bench {

const CompactMesh& lion_head(int levels) {
  static std::map<int, std::unique_ptr<CompactMesh>> cache;
  auto& slot = cache[levels];
  if (!slot) {
    slot = std::make_unique<CompactMesh>(
        test::subdivide_midpoint(test::cgal_mesh("lion-head.off"), levels));
  }
  return *slot;
}

}  // namespace ricci::bench
