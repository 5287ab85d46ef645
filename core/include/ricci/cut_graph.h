// A cut graph that opens a surface into a disk (tree-cotree, Eppstein; Erickson and Whittlesey),
// pruned of the branches that cut nothing, and split into the paths that the cut's two sides are
// glued along.
#pragma once

#include <vector>

#include "ricci/triangulation.h"

namespace ricci {

//! A path of cut edges between two nodes of the cut graph (vertices where the cut branches or
//! meets the boundary), walked from vertices[0] to vertices.back().
struct CutPath {
  std::vector<int> vertices;  //!< edges.size() + 1 vertices
  std::vector<int> edges;
};

struct CutGraph {
  std::vector<char> cut;       //!< per edge: 1 where the surface is cut open (never boundary)
  std::vector<CutPath> paths;  //!< the cut edges, grouped into paths between nodes
  int num_generators = 0;      //!< 2 genus + (boundary loops - 1): the homology the cut kills
};

//! The cut: edges outside a breadth-first spanning tree of the dual graph (from `seed_face`,
//! across interior edges), then pruned: a cut edge with an end where no other cut or boundary edge
//! meets is glued back, until none is left. What remains cuts the surface into a disk: nothing
//! for a disk or a sphere, 2g loops for a closed genus-g surface, and on surfaces with several
//! boundaries also paths joining the boundary loops.
CutGraph cut_to_disk(const Triangulation& mesh, int seed_face = 0);

}  // namespace ricci
