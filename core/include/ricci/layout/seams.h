// The seams of an atlas: a cut graph on chosen edges (the user's, where the mesh delivered is a
// subdivision of theirs) that passes through every cone of a flat cone metric and opens the
// surface into a disk, so the metric lays out in the plane.
//
//   homology     2g short loops (Erickson and Whittlesey's greedy), on the surface with each
//                boundary loop contracted to a point (a loop through one is cut as arcs that end
//                on it): a tree of shortest paths from a central vertex, the dual tree of the
//                longest loops across the other edges, and the 2g edges left, each with its two
//                tree paths to the root;
//   connections  the cones, the boundary loops and those loops joined by a Steiner tree of
//                shortest paths (Mehlhorn's 2-approximation: nearest-terminal regions, the
//                cheapest bridges between them in Kruskal's order);
//   wide cones   a cone of angle above 2 pi laid out on one branch would overlap itself around
//                its vertex: its wedges wider than asked are split near their middles (each
//                new branch a shortest path to the cut, ending some cut edges away);
//   pruning      branches that end at no cone glued back.
#pragma once

#include <limits>
#include <vector>

#include "ricci/layout/cut_graph.h"
#include "ricci/mesh/triangulation.h"

namespace ricci {

//! How wide a cone's wedges (its angle between two cut edges that follow each other around it)
//! may be: a cone of angle above 2 pi laid out as one wedge overlaps itself around its vertex,
//! and a wedge near a full turn can overlap the far side of its own chart.
struct ConeWedges {
  //! The flat metric's, per corner 3 f + c (empty: no limit); only those at cones are read.
  std::vector<double> corner_angles;
  double widest = std::numeric_limits<double>::infinity();
  //! A further branch ends on the cut at least this far from its cone along the cut (in
  //! `lengths`): ended at the nearest cut vertex it closes a loop around a few faces by the cone.
  double branch_end = 0;
};

//! A cut through the cones (`cones`) on the edges marked in `allowed` (per edge; empty: every
//! edge), with `lengths` per edge the weights of shortest paths (3D lengths: seams short on the
//! surface the user sees). Each cone's widest wedge, while wider than `wedges.widest`, gets a
//! branch that leaves the cone where both parts are within it (the wedge's middle half if it is
//! more than twice as wide), the shortest such path to a cut vertex `wedges.branch_end` or more
//! from the cone along the cut.
//! Cones are nodes of the cut's paths, so every path's two sides are related by one isometry.
//! \pre the allowed edges connect every vertex; cones are interior vertices.
CutGraph cut_through_cones(const Triangulation& mesh, const std::vector<double>& lengths,
                           const std::vector<int>& cones, const ConeWedges& wedges = {},
                           const std::vector<char>& allowed = {});

//! Joins the pieces of the cut-and-boundary graph (`cut` per edge) into one by shortest paths on
//! the allowed edges (the same Steiner tree): a cut that contains a cut graph to a disk and is
//! connected opens the surface into disks only.
void connect_cut(const Triangulation& mesh, const std::vector<double>& lengths,
                 std::vector<char>& cut, const std::vector<char>& allowed = {});

//! The total length of the cut's edges in `lengths`.
double cut_length(const Triangulation& mesh, const CutGraph& cut,
                  const std::vector<double>& lengths);

}  // namespace ricci
