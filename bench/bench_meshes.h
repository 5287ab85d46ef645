// Benchmark meshes: a real disk scan from the CGAL data set, refined by midpoint subdivision.
#pragma once

#include <string>

#include "ricci/mesh/compact_mesh.h"

namespace ricci::bench {

//! lion-head.off (a disk, 16674 faces) subdivided `levels` times; cached per level.
const CompactMesh& lion_head(int levels);

}  // namespace ricci::bench
