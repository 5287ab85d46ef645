// An atlas drawn on a common subdivision, moved onto the user's own triangles
// (pipeline/texture_atlas.h).
//
// The seams run on the user's edges, so each input face lies in one chart, and its corners are
// vertices of the subdivision: the charts' corners at the input's vertices are the flat cone
// metric's, and a chart's border between two of them, a polyline through the subdivision's new
// vertices, becomes its chord. The two sides of a seam are congruent polylines, so their chords
// are equal too: the seams still glue.
#include <algorithm>

#include "pipeline/texture_atlas.h"
#include "ricci/layout/charts.h"

namespace ricci::detail {

std::optional<InputCharts> charts_on_input(const CompactMesh& mesh, const CommonSubdivision& sub,
                                           const Triangulation& delivered,
                                           const std::vector<int>& under,
                                           const std::vector<char>& seam, const Charts& charts) {
  const int nv = mesh.num_vertices();
  if (sub.num_input_vertices != nv) return std::nullopt;  // not this mesh's subdivision
  // Per input edge its delivered edges and how many of them are seams: all or none.
  InputCharts out;
  out.seam.assign(mesh.num_edges(), 0);
  std::vector<int> pieces(mesh.num_edges(), 0), seams(mesh.num_edges(), 0);
  for (int e = 0; e < delivered.num_edges(); ++e) {
    const int on = under[e];
    if (on < 0) {
      if (seam[e]) return std::nullopt;  // a seam inside an input face
      continue;
    }
    ++pieces[on];
    seams[on] += seam[e] != 0;
  }
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (seams[e] != 0 && seams[e] != pieces[e]) return std::nullopt;
    out.seam[e] = seams[e] != 0;
  }
  // Per input face, its pieces' chart and its corners where they put them.
  Charts& in = out.charts;
  in.num_charts = charts.num_charts;
  in.chart.assign(mesh.num_faces(), -1);
  in.corners.resize(mesh.num_faces());
  std::vector<char> placed(3 * static_cast<size_t>(mesh.num_faces()), 0);
  for (int h = 0; h < delivered.num_faces(); ++h) {
    const int f = sub.input_face[h];
    if (in.chart[f] >= 0 && in.chart[f] != charts.chart[h]) return std::nullopt;
    in.chart[f] = charts.chart[h];
    for (int k = 0; k < 3; ++k) {
      const int v = sub.faces[h][k];
      if (v >= nv) continue;
      for (int c = 0; c < 3; ++c) {
        if (mesh.faces()[f][c] != v) continue;
        in.corners[f][c] = charts.corners[h][k];
        placed[3 * static_cast<size_t>(f) + c] = 1;
      }
    }
  }
  if (std::find(placed.begin(), placed.end(), 0) != placed.end()) return std::nullopt;
  in.max_relative_length_error = charts.max_relative_length_error;
  return out;
}

std::vector<char> pieces_closure(const CompactMesh& mesh, const std::vector<int>& under,
                                 const std::vector<int>& faces) {
  std::vector<int> pieces(mesh.num_edges(), 0);
  for (int e : under) {
    if (e >= 0) ++pieces[e];
  }
  std::vector<char> cut_up(mesh.num_faces(), 0);
  std::vector<int> queue;
  for (int f : faces) {
    if (!cut_up[f]) cut_up[f] = 1, queue.push_back(f);
  }
  while (!queue.empty()) {
    const int f = queue.back();
    queue.pop_back();
    for (int c = 0; c < 3; ++c) {
      if (pieces[mesh.face_edge(f, c)] < 2) continue;
      const int across = mesh.twin(3 * f + c);
      if (across >= 0 && !cut_up[across / 3]) cut_up[across / 3] = 1, queue.push_back(across / 3);
    }
  }
  return cut_up;
}

PartlyCutCharts partly_cut_charts(const CompactMesh& mesh, const CommonSubdivision& sub,
                                  const Triangulation& delivered, const std::vector<char>& seam,
                                  const Charts& pieces, const InputCharts& in,
                                  const std::vector<char>& cut_up) {
  const int nv = mesh.num_vertices();
  CommonSubdivision s;
  s.num_input_vertices = nv;
  s.num_flips = sub.num_flips;
  s.seconds = sub.seconds;
  // Each input face's pieces; a face of one piece is its own (its corners the piece's).
  std::vector<std::vector<int>> pieces_of(mesh.num_faces());
  for (int h = 0; h < delivered.num_faces(); ++h) {
    if (cut_up[sub.input_face[h]]) pieces_of[sub.input_face[h]].push_back(h);
  }
  // The vertices: the input's, then the new ones that the cut faces' pieces hold.
  std::vector<int> index(sub.positions.size(), -1);
  std::vector<int> kept;
  for (int v = 0; v < nv; ++v) index[v] = v, kept.push_back(v);
  for (const std::vector<int>& list : pieces_of) {
    for (int h : list) {
      for (int v : sub.faces[h]) {
        if (index[v] < 0) index[v] = static_cast<int>(kept.size()), kept.push_back(v);
      }
    }
  }
  s.u.resize(static_cast<long>(kept.size()));
  for (size_t i = 0; i < kept.size(); ++i) {
    const int v = kept[i];
    s.positions.push_back(sub.positions[v]);
    s.u[static_cast<long>(i)] = sub.u[v];
    s.vertex_input_face.push_back(sub.vertex_input_face[v]);
    s.vertex_barycentric.push_back(sub.vertex_barycentric[v]);
    if (v >= nv) {
      s.vertex_input_edge.push_back(sub.vertex_input_edge[v - nv]);
      s.vertex_edge_parameter.push_back(sub.vertex_edge_parameter[v - nv]);
    }
  }
  // The faces in the input's order, a cut one's pieces in its place, each with its chart, its
  // corners and the seams of its sides.
  Charts charts;
  int input_faces_cut = 0;
  charts.num_charts = pieces.num_charts;
  charts.max_relative_length_error = pieces.max_relative_length_error;
  std::vector<std::array<char, 3>> side_seam;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const std::array<int, 3>& own = mesh.faces()[f];
    if (pieces_of[f].size() > 1) {
      ++input_faces_cut;
      for (int h : pieces_of[f]) {
        std::array<int, 3> t{};
        std::array<char, 3> on{};
        for (int c = 0; c < 3; ++c) {
          t[c] = index[sub.faces[h][c]];
          on[c] = seam[delivered.face_edge(h, c)];
        }
        s.faces.push_back(t);
        s.input_face.push_back(f);
        s.final_face.push_back(sub.final_face[h]);
        charts.chart.push_back(pieces.chart[h]);
        charts.corners.push_back(pieces.corners[h]);
        side_seam.push_back(on);
      }
      continue;
    }
    std::array<char, 3> on{};
    for (int c = 0; c < 3; ++c) on[c] = in.seam[mesh.face_edge(f, c)];
    s.faces.push_back(own);
    s.input_face.push_back(f);
    side_seam.push_back(on);
    if (pieces_of[f].empty()) {
      s.final_face.push_back(-1);
      charts.chart.push_back(in.charts.chart[f]);
      charts.corners.push_back(in.charts.corners[f]);
      continue;
    }
    // Its one piece: the face itself, its corners from a turn of the piece's.
    const int h = pieces_of[f][0];
    int turn = 0;
    while (turn < 2 && sub.faces[h][turn] != own[0]) ++turn;
    s.final_face.push_back(sub.final_face[h]);
    charts.chart.push_back(pieces.chart[h]);
    charts.corners.push_back({pieces.corners[h][turn], pieces.corners[h][(turn + 1) % 3],
                              pieces.corners[h][(turn + 2) % 3]});
  }
  Triangulation t = Triangulation::from_faces(static_cast<int>(kept.size()), s.faces);
  std::vector<char> sides(t.num_edges(), 0);
  for (int f = 0; f < t.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) sides[t.face_edge(f, c)] |= side_seam[f][c];
  }
  s.corners.resize(s.faces.size());
  s.vertex_layout.assign(kept.size(), Eigen::Vector3d::Zero());
  for (size_t f = 0; f < s.faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector2d& q = charts.corners[f][c];
      s.corners[f][c] = Eigen::Vector3d(q.x(), q.y(), 0);
    }
  }
  for (size_t f = s.faces.size(); f-- > 0;) {  // each vertex from the first face that holds it
    for (int c = 0; c < 3; ++c) s.vertex_layout[s.faces[f][c]] = s.corners[f][c];
  }
  return {std::move(s), std::move(t), std::move(sides), std::move(charts), input_faces_cut};
}

}  // namespace ricci::detail
