// What every cut graph does once its edges are chosen (ricci/layout/cut_graph.h, seams.h): pruning
// the branches that cut nothing, and splitting the cut into the paths its two sides are glued
// along. Not installed API.
#pragma once

#include <vector>

#include "ricci/layout/cut_graph.h"
#include "ricci/mesh/triangulation.h"

namespace ricci::detail {

//! Glues back every cut edge with an end where no other cut or boundary edge meets and that is
//! not a kept vertex (`keep` per vertex, or empty), until none is left. Returns each vertex's
//! number of cut and boundary edges.
std::vector<int> prune_cut(const Triangulation& mesh, std::vector<char>& cut,
                           const std::vector<char>& keep);

//! The cut edges as paths between nodes (vertices of degree != 2 in the cut-and-boundary graph,
//! on the boundary, or marked in `nodes`, which may be empty), and loops through no node.
std::vector<CutPath> split_cut_into_paths(const Triangulation& mesh, const std::vector<char>& cut,
                                          const std::vector<int>& degree,
                                          const std::vector<char>& nodes);

}  // namespace ricci::detail
