// Meshes shared by the tests and benchmarks: generated smooth meshes of each topology, and real
// meshes from the CC0 data set of Debian's libcgal-demo (fetched by scripts/setup.sh).
#pragma once

#include <string>
#include <vector>

#include "ricci/flow/flow_result.h"
#include "ricci/flow/scheme.h"
#include "ricci/mesh/compact_mesh.h"

namespace ricci::test {

//! A bumpy disk: an n x n grid mapped onto the unit disk, lifted to z = 0.3 exp(-2 r^2).
CompactMesh bumpy_disk(int n);
//! The planar square [0,1]^2 split into n x n cells of two triangles.
CompactMesh square_grid(int n);
//! A torus of revolution, n x m quads split into triangles.
CompactMesh torus(int n, int m, double major = 1.0, double minor = 0.4);
//! An icosahedron subdivided `levels` times and projected to an ellipsoid with semi-axes a, b, c.
CompactMesh ellipsoid(int levels, double a = 1.0, double b = 1.0, double c = 1.0);
//! Splits every triangle into four at its edge midpoints, `levels` times (faces x 4^levels).
CompactMesh subdivide_midpoint(const CompactMesh& mesh, int levels);
//! A mesh from the CGAL data set, e.g. "eight.off".
CompactMesh cgal_mesh(const std::string& name);
//! Path of a file in the CGAL data set.
std::string cgal_mesh_path(const std::string& name);
//! Per vertex its row among the interior vertices (in vertex order), -1 on the boundary.
std::vector<int> interior_rows(const CompactMesh& mesh);

//! The options of `scheme` on mesh, with eps -1, 0, +1 in turn over the vertices (used by the mixed
//! scheme only).
SchemeOptions scheme_options(Scheme scheme, const CompactMesh& mesh);

//! The flow's default options with edge flips off (EdgeFlips::Never).
FlowOptions without_flips();

}  // namespace ricci::test
