// The inside of a chart redrawn as the harmonic map of its border, and faces drawn turned over
// untangled (ricci/layout/charts.h).
//
// A common subdivision's pieces are drawn one by one from the flowed metric, and their new
// vertices sit where the flow's crossings put them; with the chart's border kept, the map of least
// conformal energy (sum over the faces of their cotangent-weighted squared sides, less the drawn
// area, which the border fixes) is the one whose wedges off the border are each the
// cotangent-weighted mean of their neighbours. The cotangent Laplacian is the Dirichlet energy of
// piecewise linear functions: positive semi-definite on every mesh, definite once the border is
// held, so one Cholesky factorization serves every chart redrawn.
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/Sparse>

#include "ricci/layout/charts.h"
#include "ricci/linear/linear_solver.h"
#include "ricci/mesh/geometry.h"

namespace ricci {

namespace {

// Per chart: the 95th percentile of its faces' quasi-conformal ratios as drawn in `corners`.
std::vector<double> chart_qc_p95(const Triangulation& mesh,
                                 const std::vector<Eigen::Vector3d>& positions,
                                 const Charts& charts, const std::vector<char>& which) {
  std::vector<std::vector<double>> qc(charts.num_charts);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (!which[charts.chart[f]]) continue;
    qc[charts.chart[f]].push_back(
        drawn_quasi_conformal_ratio(positions, mesh.faces()[f], charts.corners[f]));
  }
  std::vector<double> p95(charts.num_charts, 0);
  for (int k = 0; k < charts.num_charts; ++k) {
    if (qc[k].empty()) continue;
    const size_t i = static_cast<size_t>(0.95 * static_cast<double>(qc[k].size() - 1));
    std::nth_element(qc[k].begin(), qc[k].begin() + static_cast<long>(i), qc[k].end());
    p95[k] = qc[k][i];
  }
  return p95;
}

// Per face corner, 1 where its wedge is on the border: at a seam or a boundary edge.
std::vector<char> border_wedges(const Triangulation& mesh, const std::vector<char>& cut,
                                const std::vector<int>& wedge) {
  const int nf = mesh.num_faces();
  std::vector<char> border(3 * static_cast<size_t>(nf), 0);
  for (int f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int h = 3 * f + c;  // the side opposite corner c: its two ends are on it
      if (mesh.twin(h) >= 0 && !cut[mesh.face_edge(f, c)]) continue;
      border[wedge[3 * f + (c + 1) % 3]] = border[wedge[3 * f + (c + 2) % 3]] = 1;
    }
  }
  return border;
}

}  // namespace

int draw_harmonic_insides(const Triangulation& mesh, const std::vector<Eigen::Vector3d>& positions,
                          const std::vector<char>& cut, const std::vector<char>& which,
                          Charts& charts) {
  const int nf = mesh.num_faces();
  const std::vector<int> wedge = chart_wedges(mesh, cut);
  std::vector<char> redrawn(charts.num_charts, 0);
  for (int k = 0; k < charts.num_charts; ++k) redrawn[k] = which[k];
  // The cotangent of each corner's 3D angle; a face of no 3D area leaves its chart as drawn.
  std::vector<std::array<double, 3>> cot(nf);
  for (int f = 0; f < nf; ++f) {
    const auto& t = mesh.faces()[f];
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d a = positions[t[(c + 1) % 3]] - positions[t[c]];
      const Eigen::Vector3d b = positions[t[(c + 2) % 3]] - positions[t[c]];
      const double twice_area = a.cross(b).norm();
      cot[f][c] = a.dot(b) / twice_area;
      if (!(twice_area > 0) || !std::isfinite(cot[f][c])) redrawn[charts.chart[f]] = 0;
    }
  }
  const std::vector<char> border = border_wedges(mesh, cut, wedge);
  std::vector<int> unknown(3 * nf, -1);
  int n = 0;
  for (int k = 0; k < 3 * nf; ++k) {
    if (redrawn[charts.chart[k / 3]] && wedge[k] == k && !border[k]) unknown[k] = n++;
  }
  if (n == 0) return 0;
  // sum over the sides of w (x_i - x_j)^2, w half the cotangent of the angle opposite.
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2);
  for (int f = 0; f < nf; ++f) {
    if (!redrawn[charts.chart[f]]) continue;
    for (int c = 0; c < 3; ++c) {
      const double w = 0.5 * cot[f][c];
      const int p = 3 * f + (c + 1) % 3, q = 3 * f + (c + 2) % 3;
      const int i = unknown[wedge[p]], j = unknown[wedge[q]];
      if (i >= 0) entries.emplace_back(i, i, w);
      if (j >= 0) entries.emplace_back(j, j, w);
      if (i >= 0 && j >= 0) {
        entries.emplace_back(i, j, -w), entries.emplace_back(j, i, -w);
      } else if (i >= 0) {
        rhs.row(i) += w * charts.corners[f][(c + 2) % 3].transpose();
      } else if (j >= 0) {
        rhs.row(j) += w * charts.corners[f][(c + 1) % 3].transpose();
      }
    }
  }
  Eigen::SparseMatrix<double> laplacian(n, n);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  LinearSolver solver(LinearSolverKind::Cholmod);
  solver.analyze(laplacian);
  if (!solver.factorize(laplacian)) return 0;
  const Eigen::MatrixXd x = solver.solve(rhs);
  if (!x.allFinite()) return 0;

  // Redrawn, then each chart checked: no face turned over, no two overlapping.
  Charts harmonic = charts;
  for (int k = 0; k < 3 * nf; ++k) {
    const int i = unknown[wedge[k]];
    if (i >= 0) harmonic.corners[k / 3][k % 3] = x.row(i).transpose();
  }
  for (int f = 0; f < nf; ++f) {
    if (redrawn[charts.chart[f]] && !(signed_area(harmonic.corners[f]) > 0)) {
      redrawn[charts.chart[f]] = 0;
    }
  }
  std::vector<char> unchanged(charts.num_charts, 0);
  for (int k = 0; k < charts.num_charts; ++k) unchanged[k] = !redrawn[k];
  for (const auto& [f, g] : overlapping_faces(mesh, cut, harmonic, unchanged)) {
    redrawn[harmonic.chart[f]] = 0;
  }
  // And the redrawn chart is kept where it is more nearly conformal on the whole, not only in
  // energy: its 95th percentile of QC no higher (on 230 real and CGAL surfaces, 9 rose without
  // this, bouncy-pie.ply's 1.61 to 1.80).
  // A chart drawn with a face turned over is redrawn whatever its QC.
  std::vector<char> compared = redrawn;
  for (int f = 0; f < nf; ++f) {
    if (!(signed_area(charts.corners[f]) > 0)) compared[charts.chart[f]] = 0;
  }
  const std::vector<double> before = chart_qc_p95(mesh, positions, charts, compared);
  const std::vector<double> after = chart_qc_p95(mesh, positions, harmonic, compared);
  for (int k = 0; k < charts.num_charts; ++k) {
    if (compared[k] && !(after[k] <= before[k])) redrawn[k] = 0;
  }
  int count = 0;
  for (int f = 0; f < nf; ++f) {
    if (redrawn[charts.chart[f]]) charts.corners[f] = harmonic.corners[f];
  }
  for (int k = 0; k < charts.num_charts; ++k) count += redrawn[k];
  return count;
}

double drawn_quasi_conformal_ratio(const std::vector<Eigen::Vector3d>& positions,
                                   const std::array<int, 3>& face,
                                   const std::array<Eigen::Vector2d, 3>& corners) {
  std::array<double, 3> from, to;  // side lengths, opposite each corner
  for (int c = 0; c < 3; ++c) {
    from[c] = (positions[face[(c + 2) % 3]] - positions[face[(c + 1) % 3]]).norm();
    to[c] = (corners[(c + 2) % 3] - corners[(c + 1) % 3]).norm();
  }
  return quasi_conformal_ratio(from, to);
}

// Rounds over the faces still turned.
constexpr int kUntangleRounds = 4;

std::vector<int> untangle_turned_faces(const Triangulation& mesh, const std::vector<char>& cut,
                                       Charts& charts) {
  const int nf = mesh.num_faces();
  const std::vector<int> wedge = chart_wedges(mesh, cut);
  const std::vector<char> border = border_wedges(mesh, cut, wedge);
  std::vector<std::vector<int>> corners_of(3 * static_cast<size_t>(nf));
  for (int k = 0; k < 3 * nf; ++k) corners_of[wedge[k]].push_back(k);
  const auto position = [&](int w) { return charts.corners[w / 3][w % 3]; };
  const auto star_positive = [&](int w) {
    for (int k : corners_of[w]) {
      if (!(signed_area(charts.corners[k / 3]) > 0)) return false;
    }
    return true;
  };
  std::vector<char> moved(3 * static_cast<size_t>(nf), 0);
  std::vector<int> wedges_moved;
  for (int round = 0; round < kUntangleRounds; ++round) {
    std::vector<int> turned;
    for (int f = 0; f < nf; ++f) {
      if (!(signed_area(charts.corners[f]) > 0)) turned.push_back(f);
    }
    if (turned.empty()) break;
    for (int f : turned) {
      for (int c = 0; c < 3 && !(signed_area(charts.corners[f]) > 0); ++c) {
        const int w = wedge[3 * f + c];
        if (border[w]) continue;
        Eigen::Vector2d sum = Eigen::Vector2d::Zero();
        for (int k : corners_of[w]) {
          sum += position(wedge[3 * (k / 3) + (k % 3 + 1) % 3]);
          sum += position(wedge[3 * (k / 3) + (k % 3 + 2) % 3]);
        }
        const Eigen::Vector2d mean = sum / (2.0 * static_cast<double>(corners_of[w].size()));
        const Eigen::Vector2d from = position(w);
        for (double t = 1.0 / 16; t <= 1; t *= 2) {
          const Eigen::Vector2d p = from + t * (mean - from);
          for (int k : corners_of[w]) charts.corners[k / 3][k % 3] = p;
          if (star_positive(w)) break;
          if (t == 1) {
            for (int k : corners_of[w]) charts.corners[k / 3][k % 3] = from;
          }
        }
        if (!(position(w) == from) && !moved[w]) moved[w] = 1, wedges_moved.push_back(w);
      }
    }
  }
  return wedges_moved;
}

}  // namespace ricci
