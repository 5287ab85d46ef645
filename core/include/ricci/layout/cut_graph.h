// A cut graph that opens a surface into a disk: the edges dual to no edge of a spanning tree of
// the dual graph, pruned of the branches that cut nothing (the cut graphs of Erickson and
// Whittlesey; no primal tree is built, so the result is a graph of 2g + b - 1 independent cycles,
// not a system of loops at one vertex), split into the paths that the cut's two sides are glued
// along.
#pragma once

#include <vector>

#include "ricci/mesh/triangulation.h"

namespace ricci {

//! A path of cut edges between two nodes of the cut graph (vertices where the cut branches or
//! meets the boundary), walked from vertices[0] to vertices.back().
struct CutPath {
  std::vector<int> vertices;  //!< edges.size() + 1 vertices
  std::vector<int> edges;
};

struct CutGraph {
  std::vector<char> cut;       //!< per edge: 1 where the surface is cut open (never boundary)
  int root = 0;                //!< the face the dual spanning tree grows from
  std::vector<CutPath> paths;  //!< the cut edges, grouped into paths between nodes
  int num_generators = 0;      //!< 2 genus + (boundary loops - 1): the homology the cut kills
};

//! The cut: interior edges outside a breadth-first spanning tree of the dual graph (from face 0),
//! then pruned: a cut edge with an end where no other cut or boundary edge meets is glued back,
//! until none is left. What remains cuts the surface into a disk: nothing for a disk or a sphere,
//! a graph with 2g independent cycles for a closed genus-g surface, and on surfaces with several
//! boundaries also paths joining the boundary loops.
CutGraph cut_to_disk(const Triangulation& mesh);

//! The same with the dual tree of shortest paths in a metric (`lengths` per edge; a step between
//! two faces weighs their mean side), grown from a face central in that metric (the middle of the
//! longest of two sweeps), so the cut disk is as round as the surface allows: a developed layout
//! then reaches no farther from its root than the surface's radius (far from the origin the
//! Poincare disk has no precision left).
CutGraph cut_to_disk(const Triangulation& mesh, const std::vector<double>& lengths);

}  // namespace ricci
