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
#include <array>
#include <cmath>
#include <optional>
#include <utility>

#include <Eigen/Geometry>
#include <Eigen/Sparse>

#include "ricci/layout/charts.h"
#include "ricci/linear/linear_solver.h"
#include "ricci/mesh/compact_mesh.h"
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
  const auto inside = [&](int k) {
    return redrawn[charts.chart[k / 3]] && wedge[k] == k && !border[k];
  };
  bool any_inside = false;
  for (int k = 0; k < 3 * nf && !any_inside; ++k) any_inside = inside(k);
  if (!any_inside) return 0;
  // A face turned over with its three corners on the border stays so, and its chart as drawn
  // (below): that chart is left out of the system (CGAL's man at 8 cones, its user's faces: a cone
  // opens the corners of three past a half turn), the others' blocks solved as with it.
  for (int f = 0; f < nf; ++f) {
    if (!redrawn[charts.chart[f]] || signed_area(charts.corners[f]) > 0) continue;
    bool held = true;
    for (int c = 0; c < 3 && held; ++c) held = border[wedge[3 * f + c]] != 0;
    if (held) redrawn[charts.chart[f]] = 0;
  }
  std::vector<int> unknown(3 * nf, -1);
  int n = 0;
  for (int k = 0; k < 3 * nf; ++k) {
    if (inside(k)) unknown[k] = n++;
  }
  // sum over the sides of w (x_i - x_j)^2, w half the cotangent of the angle opposite. (None
  // where every chart with an inside was left out: the checks below count the others as before.)
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2), x(0, 2);
  for (int f = 0; f < nf && n > 0; ++f) {
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
  if (n > 0) {
    Eigen::SparseMatrix<double> laplacian(n, n);
    laplacian.setFromTriplets(entries.begin(), entries.end());
    LinearSolver solver(LinearSolverKind::Cholmod);
    solver.analyze(laplacian);
    if (!solver.factorize(laplacian)) return 0;
    x = solver.solve(rhs);
    if (!x.allFinite()) return 0;
  }

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

// The two sides of a seam at a vertex are taken as congruent where the rotations read from its two
// seam edges agree to this, relative to the edges' lengths: a vertex inside a seam's path, not a
// cone on it.
constexpr double kSameRotation = 1e-6;

namespace {

// The seam beside each wedge: per wedge, its vertex's neighbours along seam edges, each as the
// wedge that draws it on this side; and which vertices are on a boundary edge.
struct SeamSides {
  std::vector<std::vector<std::pair<int, int>>> neighbours;  // (vertex, its wedge on this side)
  std::vector<std::vector<int>> wedges;                      // per vertex, its wedges
  std::vector<char> on_boundary;                             // per vertex
};

SeamSides seam_sides(const Triangulation& mesh, const std::vector<char>& cut,
                     const std::vector<int>& wedge) {
  SeamSides s;
  s.neighbours.resize(3 * static_cast<size_t>(mesh.num_faces()));
  s.wedges.resize(mesh.num_vertices());
  s.on_boundary.assign(mesh.num_vertices(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = 3 * f + (c + 1) % 3, b = 3 * f + (c + 2) % 3;  // the side opposite c
      const int va = mesh.faces()[f][(c + 1) % 3], vb = mesh.faces()[f][(c + 2) % 3];
      if (mesh.twin(3 * f + c) < 0) {
        s.on_boundary[va] = s.on_boundary[vb] = 1;
      } else if (cut[mesh.face_edge(f, c)]) {
        s.neighbours[wedge[a]].emplace_back(vb, wedge[b]);
        s.neighbours[wedge[b]].emplace_back(va, wedge[a]);
      }
      std::vector<int>& at = s.wedges[mesh.faces()[f][c]];
      if (std::find(at.begin(), at.end(), wedge[3 * f + c]) == at.end()) {
        at.push_back(wedge[3 * f + c]);
      }
    }
  }
  return s;
}

// A vertex inside a seam's path: its two wedges, one on each side, and the rotation that takes the
// drawing around the first to the drawing around the second (the two sides are congruent).
struct Glued {
  int first, second;
  Eigen::Rotation2Dd rotation;
};

std::optional<Glued> glued(const SeamSides& s, int v, const Charts& charts) {
  if (s.on_boundary[v] || s.wedges[v].size() != 2) return std::nullopt;
  const int w1 = s.wedges[v][0], w2 = s.wedges[v][1];
  const auto& n1 = s.neighbours[w1];
  const auto& n2 = s.neighbours[w2];
  if (n1.size() != 2 || n2.size() != 2 || n1[0].first == n1[1].first) return std::nullopt;
  const auto position = [&](int w) { return charts.corners[w / 3][w % 3]; };
  std::array<Eigen::Vector2d, 2> side1, side2;  // the seam's edges from v on each side
  for (int i = 0; i < 2; ++i) {
    const auto same = std::find_if(
        n2.begin(), n2.end(), [&](const std::pair<int, int>& n) { return n.first == n1[i].first; });
    if (same == n2.end()) return std::nullopt;
    side1[i] = position(n1[i].second) - position(w1);
    side2[i] = position(same->second) - position(w2);
  }
  // The rotation nearest to taking both edges of one side to the other's.
  double sine = 0, cosine = 0;
  for (int i = 0; i < 2; ++i) {
    sine += side1[i].x() * side2[i].y() - side1[i].y() * side2[i].x();
    cosine += side1[i].dot(side2[i]);
  }
  const Glued g{w1, w2, Eigen::Rotation2Dd(std::atan2(sine, cosine))};
  for (int i = 0; i < 2; ++i) {
    if (!((g.rotation * side1[i] - side2[i]).norm() <= kSameRotation * side2[i].norm())) {
      return std::nullopt;
    }
  }
  return g;
}

// Rings of faces grown around a group of faces still turned, at most, and the faces a region
// may hold.
constexpr int kRegionRings = 4;
constexpr int kRegionFaces = 4096;

// Each group of faces still turned (joined through shared wedges), with the faces within a few
// rings of it, redrawn: the region's wedges that reach outside it and the border's held, every
// other wedge at the mean of its neighbours in the mean value weights of its 3D star (Floater's:
// positive, so the map is a convex combination map, an embedding where the held polygon is convex,
// by Tutte's theorem, and near the drawing the 3D shapes would give). From one ring to
// kRegionRings, the first is kept where every face with a wedge solved for turns
// counter-clockwise, some of them turned before (a face with no such wedge, turned at a cone,
// keeps its corners and does not hold the rest). Returns the wedges moved.
std::vector<int> redraw_tangled_regions(const Triangulation& mesh,
                                        const std::vector<Eigen::Vector3d>& positions,
                                        const std::vector<int>& wedge,
                                        const std::vector<char>& border,
                                        const std::vector<std::vector<int>>& corners_of,
                                        Charts& charts) {
  const int nf = mesh.num_faces();
  std::vector<int> moved;
  std::vector<char> grouped(nf, 0);
  std::vector<int> stamp(nf, -1), unknown(3 * static_cast<size_t>(nf), -1);
  const auto turned = [&](int f) { return !(signed_area(charts.corners[f]) > 0); };
  // The faces that share a wedge with face f.
  const auto around = [&](int f, const auto& visit) {
    for (int c = 0; c < 3; ++c) {
      for (int k : corners_of[wedge[3 * f + c]]) visit(k / 3);
    }
  };
  int stamp_count = 0;
  for (int seed = 0; seed < nf; ++seed) {
    if (grouped[seed] || !turned(seed)) continue;
    std::vector<int> region{seed};
    grouped[seed] = 1;
    for (size_t i = 0; i < region.size(); ++i) {
      around(region[i], [&](int g) {
        if (!grouped[g] && turned(g)) grouped[g] = 1, region.push_back(g);
      });
    }
    const int id = stamp_count++;
    for (int f : region) stamp[f] = id;
    size_t last_ring = 0;  // where the faces the last ring added begin
    for (int ring = 1; ring <= kRegionRings; ++ring) {
      const size_t before = region.size();
      for (size_t i = last_ring; i < before; ++i) {
        around(region[i], [&](int g) {
          if (stamp[g] != id) stamp[g] = id, region.push_back(g);
        });
      }
      last_ring = before;
      if (static_cast<int>(region.size()) > kRegionFaces) break;
      // The free wedges: off the border, every corner in the region.
      std::vector<int> solved;
      for (int f : region) {
        for (int c = 0; c < 3; ++c) {
          const int w = wedge[3 * f + c];
          if (border[w] || unknown[w] >= 0) continue;
          bool inside = true;
          for (int k : corners_of[w]) inside = inside && stamp[k / 3] == id;
          if (inside) unknown[w] = static_cast<int>(solved.size()), solved.push_back(w);
        }
      }
      bool kept = false;
      if (!solved.empty()) {
        const int n = static_cast<int>(solved.size());
        std::vector<Eigen::Triplet<double>> entries;
        Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2);
        for (int i = 0; i < n; ++i) {
          for (int k : corners_of[solved[i]]) {
            const int f = k / 3, c = k % 3;
            const std::array<int, 3>& t = mesh.faces()[f];
            const Eigen::Vector3d& x = positions[t[c]];
            const Eigen::Vector3d a = positions[t[(c + 1) % 3]] - x;
            const Eigen::Vector3d b = positions[t[(c + 2) % 3]] - x;
            const double angle = angle_between(a, b);
            const double half_tangent = std::tan(std::min(angle, kPi - 1e-3) / 2);
            for (int side = 1; side <= 2; ++side) {
              const int neighbour = wedge[3 * f + (c + side) % 3];
              const double length = (side == 1 ? a : b).norm();
              double weight = half_tangent / length;
              if (!(weight > 0) || !std::isfinite(weight)) weight = 1;
              entries.emplace_back(i, i, weight);
              if (unknown[neighbour] >= 0) {
                entries.emplace_back(i, unknown[neighbour], -weight);
              } else {
                rhs.row(i) += weight * charts.corners[neighbour / 3][neighbour % 3].transpose();
              }
            }
          }
        }
        Eigen::SparseMatrix<double> system(n, n);
        system.setFromTriplets(entries.begin(), entries.end());
        Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(system);
        const Eigen::MatrixXd x =
            lu.info() == Eigen::Success ? Eigen::MatrixXd(lu.solve(rhs)) : Eigen::MatrixXd();
        if (x.size() > 0 && x.allFinite()) {
          // Kept where every face with a corner solved for turns counter-clockwise: the others
          // keep their corners (a face turned at a cone stays so, and does not hold the rest).
          std::vector<std::array<Eigen::Vector2d, 3>> drawn(region.size());
          kept = true;
          bool mended = false;  // a face turned before, counter-clockwise now
          for (size_t r = 0; r < region.size() && kept; ++r) {
            bool solved_corner = false;
            for (int c = 0; c < 3; ++c) {
              const int i = unknown[wedge[3 * region[r] + c]];
              solved_corner = solved_corner || i >= 0;
              drawn[r][c] =
                  i >= 0 ? Eigen::Vector2d(x.row(i).transpose()) : charts.corners[region[r]][c];
            }
            kept = !solved_corner || signed_area(drawn[r]) > 0;
            mended = mended || (solved_corner && turned(region[r]));
          }
          kept = kept && mended;
          if (kept) {
            for (int w : solved) {
              if (!(x.row(unknown[w]).transpose() == charts.corners[w / 3][w % 3])) {
                moved.push_back(w);
              }
            }
            for (size_t r = 0; r < region.size(); ++r) charts.corners[region[r]] = drawn[r];
          }
        }
      }
      for (int w : solved) unknown[w] = -1;
      if (kept) break;
    }
  }
  return moved;
}

}  // namespace

std::vector<int> untangle_turned_faces(const Triangulation& mesh,
                                       const std::vector<Eigen::Vector3d>& positions,
                                       const std::vector<char>& cut, Charts& charts) {
  const int nf = mesh.num_faces();
  if (std::all_of(charts.corners.begin(), charts.corners.end(),
                  [](const auto& t) { return signed_area(t) > 0; })) {
    return {};  // nothing turned: the wedges and seams below are not needed
  }
  const std::vector<int> wedge = chart_wedges(mesh, cut);
  const std::vector<char> border = border_wedges(mesh, cut, wedge);
  const SeamSides seams = seam_sides(mesh, cut, wedge);
  std::vector<std::vector<int>> corners_of(3 * static_cast<size_t>(nf));
  for (int k = 0; k < 3 * nf; ++k) corners_of[wedge[k]].push_back(k);
  const auto position = [&](int w) { return charts.corners[w / 3][w % 3]; };
  const auto place = [&](int w, const Eigen::Vector2d& p) {
    for (int k : corners_of[w]) charts.corners[k / 3][k % 3] = p;
  };
  const auto star_positive = [&](int w) {
    for (int k : corners_of[w]) {
      if (!(signed_area(charts.corners[k / 3]) > 0)) return false;
    }
    return true;
  };
  // The sum of w's neighbours around its star (each twice inside a chart), about w's position.
  const auto neighbour_sum = [&](int w, int& count) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (int k : corners_of[w]) {
      sum += position(wedge[3 * (k / 3) + (k % 3 + 1) % 3]) - position(w);
      sum += position(wedge[3 * (k / 3) + (k % 3 + 2) % 3]) - position(w);
      count += 2;
    }
    return sum;
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
        // Off the border a wedge moves alone; inside a seam's path with its copy on the seam's
        // other side, towards the mean of its neighbours on both, by the seam's rotation, so that
        // the two sides stay congruent.
        int w = wedge[3 * f + c], other = -1;
        Eigen::Rotation2Dd rotation(0.0);
        int count = 0;
        Eigen::Vector2d step;
        if (!border[w]) {
          step = neighbour_sum(w, count);
        } else if (const std::optional<Glued> g = glued(seams, mesh.faces()[f][c], charts)) {
          w = g->first, other = g->second, rotation = g->rotation;
          step = neighbour_sum(w, count);
          step += rotation.inverse() * neighbour_sum(other, count);
        } else {
          continue;
        }
        step /= count;
        const Eigen::Vector2d from = position(w);
        const Eigen::Vector2d from_other = other >= 0 ? position(other) : from;
        for (double t = 1.0 / 16; t <= 1; t *= 2) {
          place(w, from + t * step);
          if (other >= 0) place(other, from_other + rotation * (t * step));
          if (star_positive(w) && (other < 0 || star_positive(other))) break;
          if (t == 1) {
            place(w, from);
            if (other >= 0) place(other, from_other);
          }
        }
        if (!(position(w) == from) && !moved[w]) moved[w] = 1, wedges_moved.push_back(w);
      }
    }
  }
  for (int w : redraw_tangled_regions(mesh, positions, wedge, border, corners_of, charts)) {
    if (!moved[w]) moved[w] = 1, wedges_moved.push_back(w);
  }
  return wedges_moved;
}

}  // namespace ricci
