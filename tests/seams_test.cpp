// Seams through cones: the cut surface is a set of disks (Euler characteristic 1 each, counted
// here from wedges, edges and faces), every cone is on the cut with the branches asked for, and
// the cut runs only on the allowed edges.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "ricci/flow/cone_placement.h"
#include "ricci/layout/seams.h"
#include "test_meshes.h"

namespace ricci::test {
namespace {

struct Pieces {
  int count = 0;
  std::vector<int> euler;  // per piece
};

// Pieces of the surface cut open (faces joined across uncut interior edges) and the Euler
// characteristic of each: wedges (a vertex's corners joined across uncut edges) - edges (uncut
// interior ones once, cut ones twice, boundary once) + faces.
Pieces cut_open(const Triangulation& mesh, const std::vector<char>& cut) {
  const int nf = mesh.num_faces();
  std::vector<int> parent(3 * nf + nf);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const auto corner = [&](int f, int v) {
    for (int c = 0; c < 3; ++c) {
      if (mesh.face_vertex(f, c) == v) return 3 * f + c;
    }
    return -1;
  };
  const int face_node = 3 * nf;
  for (int h = 0; h < 3 * nf; ++h) {
    const int t = mesh.twin(h);
    if (t < 0 || cut[mesh.face_edge(h / 3, h % 3)]) continue;
    parent[find(face_node + h / 3)] = find(face_node + t / 3);
    for (int v : {mesh.halfedge_tail(h), mesh.halfedge_head(h)}) {
      parent[find(corner(h / 3, v))] = find(corner(t / 3, v));
    }
  }
  std::vector<int> piece_of_root(parent.size(), -1);
  Pieces p;
  for (int f = 0; f < nf; ++f) {
    int& k = piece_of_root[find(face_node + f)];
    if (k < 0) k = p.count++;
  }
  p.euler.assign(p.count, 0);
  const auto piece = [&](int f) { return piece_of_root[find(face_node + f)]; };
  std::vector<char> wedge_counted(3 * nf, 0);
  for (int k = 0; k < 3 * nf; ++k) {
    const int r = find(k);
    if (!wedge_counted[r]) wedge_counted[r] = 1, ++p.euler[piece(k / 3)];
  }
  for (int f = 0; f < nf; ++f) ++p.euler[piece(f)];
  for (int h = 0; h < 3 * nf; ++h) {
    const int t = mesh.twin(h);
    if (t >= 0 && t < h && !cut[mesh.face_edge(h / 3, h % 3)]) continue;  // counted from t
    --p.euler[piece(h / 3)];
  }
  return p;
}

std::vector<int> cone_vertices(const ConePlacement& p) {
  std::vector<int> v;
  for (const Cone& c : p.cones) v.push_back(c.vertex);
  return v;
}

TEST(Seams, TheCutThroughTheConesOpensEveryTopologyIntoDisks) {
  for (const char* name : {"eight.off", "knot1.off", "elephant.off", "nefertiti.off", "pipe.off"}) {
    SCOPED_TRACE(name);
    const CompactMesh mesh = cgal_mesh(name);
    const std::vector<int> cones = cone_vertices(place_cones(mesh));
    const CutGraph g = cut_through_cones(mesh, mesh.input_lengths(), cones);
    const Pieces pieces = cut_open(mesh, g.cut);
    ASSERT_GE(pieces.count, 1);
    for (int chi : pieces.euler) EXPECT_EQ(chi, 1);
    std::vector<int> degree(mesh.num_vertices(), 0);
    for (int e = 0; e < mesh.num_edges(); ++e) {
      EXPECT_FALSE(g.cut[e] && mesh.is_boundary_edge(e));
      if (!g.cut[e]) continue;
      for (int v : mesh.edge_vertices(e)) ++degree[v];
    }
    for (int c : cones) EXPECT_GE(degree[c], 1) << "cone " << c;
    // No branch ends at a vertex that is no cone (pruned).
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (degree[v] == 1 && !mesh.is_boundary_vertex(v)) {
        EXPECT_NE(std::find(cones.begin(), cones.end(), v), cones.end()) << "vertex " << v;
      }
    }
  }
}

TEST(Seams, ASurfaceWithHandlesAndBoundaryIsCutIntoOneDisk) {
  // Without cones the cut is the boundary and 2g loops' arcs: one disk. With the boundary loops
  // capped instead of contracted, a loop running along a cap's rim twice left arcs with both ends
  // on one boundary loop, which cut regions off (20 pieces on the elephant).
  for (const char* name : {"double-torus-3-holes.off", "elephant-with-holes.off"}) {
    SCOPED_TRACE(name);
    const CompactMesh mesh = cgal_mesh(name);
    ASSERT_GT(mesh.genus(), 0);
    ASSERT_GT(mesh.num_boundary_loops(), 0);
    const CutGraph g = cut_through_cones(mesh, mesh.input_lengths(), {});
    const Pieces pieces = cut_open(mesh, g.cut);
    EXPECT_EQ(pieces.count, 1);
    for (int chi : pieces.euler) EXPECT_EQ(chi, 1);
  }
}

TEST(Seams, AConeAskingForBranchesGetsThem) {
  const CompactMesh mesh = cgal_mesh("eight.off");
  const std::vector<int> cones = cone_vertices(place_cones(mesh));
  std::vector<int> branches(cones.size(), 1);
  branches[0] = 3;
  const CutGraph g = cut_through_cones(mesh, mesh.input_lengths(), cones, branches);
  int degree = 0;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto ends = mesh.edge_vertices(e);
    degree += g.cut[e] && (ends[0] == cones[0] || ends[1] == cones[0]);
  }
  EXPECT_GE(degree, 3);
  for (int chi : cut_open(mesh, g.cut).euler) EXPECT_EQ(chi, 1);
}

TEST(Seams, TheCutRunsOnlyOnAllowedEdges) {
  // Midpoint subdivision: the fine edges on the coarse mesh's edges are those with a coarse vertex
  // at one end; the seams must stay on them, as on a common subdivision's input edges.
  const CompactMesh coarse = cgal_mesh("eight.off");
  const CompactMesh fine = subdivide_midpoint(coarse, 1);
  std::vector<char> allowed(fine.num_edges(), 0);
  for (int e = 0; e < fine.num_edges(); ++e) {
    const auto [a, b] = fine.edge_vertices(e);
    allowed[e] = a < coarse.num_vertices() || b < coarse.num_vertices();
  }
  const std::vector<int> cones = cone_vertices(place_cones(coarse));
  const CutGraph g = cut_through_cones(fine, fine.input_lengths(), cones, {}, allowed);
  for (int e = 0; e < fine.num_edges(); ++e) EXPECT_FALSE(g.cut[e] && !allowed[e]);
  for (int chi : cut_open(fine, g.cut).euler) EXPECT_EQ(chi, 1);
}

TEST(Seams, ConnectingTheCutKeepsEveryPieceADisk) {
  // A closed loop of seams around a vertex's star, apart from the rest of the cut, would cut out
  // an annulus; connect_cut joins it to the cut.
  const CompactMesh mesh = cgal_mesh("eight.off");
  const std::vector<int> cones = cone_vertices(place_cones(mesh));
  std::vector<char> cut = cut_through_cones(mesh, mesh.input_lengths(), cones).cut;
  // A vertex whose star's vertices are all off the cut.
  std::vector<char> on_cut(mesh.num_vertices(), 0);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (cut[e]) on_cut[mesh.edge_vertices(e)[0]] = on_cut[mesh.edge_vertices(e)[1]] = 1;
  }
  std::vector<char> near_cut = on_cut;
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [a, b] = mesh.edge_vertices(e);
    if (on_cut[a] || on_cut[b]) near_cut[a] = near_cut[b] = 1;
  }
  const int far =
      static_cast<int>(std::find(near_cut.begin(), near_cut.end(), 0) - near_cut.begin());
  ASSERT_LT(far, mesh.num_vertices());
  // The link of `far`: the edges of its faces opposite it.
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      if (mesh.face_vertex(f, c) == far) cut[mesh.face_edge(f, c)] = 1;
    }
  }
  const Pieces before = cut_open(mesh, cut);
  EXPECT_NE(std::count(before.euler.begin(), before.euler.end(), 0), 0);  // the annulus
  connect_cut(mesh, mesh.input_lengths(), cut);
  for (int chi : cut_open(mesh, cut).euler) EXPECT_EQ(chi, 1);
}

}  // namespace
}  // namespace ricci::test
