// Seams through cones: the cut surface is a set of disks (Euler characteristic 1 each, counted
// here from wedges, edges and faces), every cone is on the cut, a wide one in wedges narrow enough,
// and the cut runs only on the allowed edges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

// The angles of vertex v's wedges: its corners joined across the uncut edges at v, each group's
// corner angles summed.
std::vector<double> wedge_angles(const Triangulation& mesh, const std::vector<char>& cut, int v,
                                 const std::vector<double>& corner_angles) {
  std::vector<int> corners;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      if (mesh.face_vertex(f, c) == v) corners.push_back(3 * f + c);
    }
  }
  std::vector<int> group(corners.size());
  std::iota(group.begin(), group.end(), 0);
  for (bool joined = true; joined;) {  // the least index over corners joined across an edge
    joined = false;
    for (size_t i = 0; i < corners.size(); ++i) {
      for (size_t j = 0; j < corners.size(); ++j) {
        const int f = corners[i] / 3, g = corners[j] / 3;
        for (int c = 0; c < 3; ++c) {
          const int t = mesh.twin(3 * f + c);
          if (t < 0 || t / 3 != g || cut[mesh.face_edge(f, c)]) continue;
          if (mesh.halfedge_tail(3 * f + c) != v && mesh.halfedge_head(3 * f + c) != v) continue;
          if (group[j] > group[i]) group[j] = group[i], joined = true;
        }
      }
    }
  }
  std::vector<double> sum(corners.size(), 0.0);
  for (size_t i = 0; i < corners.size(); ++i) sum[group[i]] += corner_angles[corners[i]];
  std::vector<double> wedges;
  for (size_t i = 0; i < corners.size(); ++i) {
    if (group[i] == static_cast<int>(i)) wedges.push_back(sum[i]);
  }
  return wedges;
}

TEST(Seams, AWideConesWedgesAreNarrowed) {
  // The 3D corner angles, three times as wide at the first cone: a cone of about 6 pi, which the
  // cut must leave in wedges of at most 1.9 pi each (one wedge would overlap itself thrice).
  const CompactMesh mesh = cgal_mesh("eight.off");
  const std::vector<int> cones = cone_vertices(place_cones(mesh));
  ConeWedges wedges{std::vector<double>(3 * static_cast<size_t>(mesh.num_faces())), 1.9 * kPi};
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const std::array<int, 3>& t = mesh.faces()[f];
      const Eigen::Vector3d u = mesh.positions()[t[(c + 1) % 3]] - mesh.positions()[t[c]];
      const Eigen::Vector3d w = mesh.positions()[t[(c + 2) % 3]] - mesh.positions()[t[c]];
      wedges.corner_angles[3 * f + c] =
          std::atan2(u.cross(w).norm(), u.dot(w)) * (t[c] == cones[0] ? 3 : 1);
    }
  }
  const CutGraph g = cut_through_cones(mesh, mesh.input_lengths(), cones, wedges);
  const std::vector<double> at_cone = wedge_angles(mesh, g.cut, cones[0], wedges.corner_angles);
  EXPECT_GE(at_cone.size(), 4u);  // about 6 pi in wedges of at most 1.9 pi
  for (double a : at_cone) EXPECT_LE(a, 1.9 * kPi);
  for (int chi : cut_open(mesh, g.cut).euler) EXPECT_EQ(chi, 1);
  // Without the corner angles no wedge is split: fewer wedges.
  const CutGraph plain = cut_through_cones(mesh, mesh.input_lengths(), cones);
  EXPECT_LT(wedge_angles(mesh, plain.cut, cones[0], wedges.corner_angles).size(), at_cone.size());
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
