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

}  // namespace ricci::detail
