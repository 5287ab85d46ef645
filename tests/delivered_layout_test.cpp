// The delivered layout as a reader of ricci-flow's PLY finds it, checked with geometry written
// here: every face's model (ricci_layout), its chart and its corners in the model's coordinates
// (layout_corners); the corner angles, measured in the model (hyperbolic angles between geodesic
// sides in the Poincare disk), sum to 2 pi - Kbar at every interior vertex, those the cut opens
// included; the two sides of every cut edge are the same edge, moved by one isometry along each
// stretch of the cut.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cli_run.h"

namespace ricci::test::cli {
namespace {

using Complex = std::complex<double>;
using LongComplex = std::complex<long double>;

constexpr int kPlane = 1, kDisk = 2;

struct Delivered {
  PlyData ply;
  std::vector<std::array<Complex, 3>> corners;  // layout_corners
  std::vector<int> model, chart;
};

Delivered run_and_read(const std::string& mesh, const std::string& options = "") {
  const std::string out = temp("result.ply");
  const CliRun r = ricci_flow(mesh + " -o " + out + " " + options);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  Delivered d;
  d.ply = read_ply(out);
  const PlyData& p = d.ply;
  EXPECT_TRUE(p.has_face("ricci_layout") && p.has_face("ricci_chart") &&
              p.has_face("layout_corners"));
  if (!p.has_face("layout_corners")) return d;
  for (size_t f = 0; f < p.faces.size(); ++f) {
    const std::vector<double>& c = p.face_lists.at("layout_corners")[f];
    EXPECT_EQ(c.size(), 6u);
    d.corners.push_back({Complex(c[0], c[1]), Complex(c[2], c[3]), Complex(c[4], c[5])});
    d.model.push_back(static_cast<int>(p.face.at("ricci_layout")[f]));
    d.chart.push_back(static_cast<int>(p.face.at("ricci_chart")[f]));
  }
  return d;
}

// The angle at p of the triangle p, q, r: in the disk, after the Moebius map taking p to 0 (the
// geodesics from p become rays), in long double (1 - conj(p) q cancels near the rim).
long double corner_angle(int model, Complex p, Complex q, Complex r) {
  LongComplex a(q - p), b(r - p);
  if (model == kDisk) {
    const LongComplex lp(p), lq(q), lr(r);
    a = (lq - lp) / (1.0L - std::conj(lp) * lq);
    b = (lr - lp) / (1.0L - std::conj(lp) * lr);
  }
  return std::abs(std::arg(b * std::conj(a)));
}

double distance(int model, Complex p, Complex q) {
  if (model == kPlane) return std::abs(p - q);
  return 2 * std::atanh(std::abs((q - p) / (1.0 - std::conj(p) * q)));
}

// The orientation-preserving isometry taking p0 to q0 and the direction of p1 from p0 to that of
// q1 from q0, applied to z.
Complex move(int model, Complex p0, Complex p1, Complex q0, Complex q1, Complex z) {
  if (model == kPlane)
    return q0 + (z - p0) * std::polar(1.0, std::arg(q1 - q0) - std::arg(p1 - p0));
  auto to_origin = [](Complex c, Complex x) { return (x - c) / (1.0 - std::conj(c) * x); };
  auto from_origin = [](Complex c, Complex x) { return (x + c) / (1.0 + std::conj(c) * x); };
  const Complex turn = std::polar(1.0, std::arg(to_origin(q0, q1)) - std::arg(to_origin(p0, p1)));
  return from_origin(q0, turn * to_origin(p0, z));
}

struct Sums {
  double worst = 0, worst_cut = 0;
  int checked = 0, cut = 0;
};

// Angle sums against 2 pi - Kbar (ricci_target; 0 at a subdivision's new vertices) at every
// interior vertex; a cut vertex is one whose corners lie at more than one position.
Sums angle_sums(const Delivered& d) {
  const PlyData& p = d.ply;
  const size_t n = p.vertex.at("x").size();
  std::vector<long double> total(n, 0);
  std::vector<Complex> first(n, Complex(NAN, NAN));
  std::vector<char> cut(n, 0);
  std::map<std::pair<int, int>, int> edge_faces;
  for (size_t f = 0; f < p.faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = p.faces[f][c], w = p.faces[f][(c + 1) % 3];
      total[v] += corner_angle(d.model[f], d.corners[f][c], d.corners[f][(c + 1) % 3],
                               d.corners[f][(c + 2) % 3]);
      if (std::isnan(first[v].real())) first[v] = d.corners[f][c];
      cut[v] |= std::abs(d.corners[f][c] - first[v]) > 1e-9;
      ++edge_faces[{std::min(v, w), std::max(v, w)}];
    }
  }
  std::vector<char> interior(n, 1);
  for (const auto& [e, count] : edge_faces) {
    if (count != 2) interior[e.first] = interior[e.second] = 0;
  }
  const bool subdivided = p.has_vertex("ricci_input_face");
  Sums s;
  for (size_t v = 0; v < n; ++v) {
    if (!interior[v] || std::isnan(first[v].real())) continue;
    const bool added = subdivided && p.vertex.at("ricci_input_face")[v] >= 0;
    const double kbar = added ? 0.0 : p.vertex.at("ricci_target")[v];
    if (std::isnan(kbar)) continue;
    const double error = static_cast<double>(std::abs(total[v] - (2 * M_PIl - kbar)));
    s.worst = std::max(s.worst, error);
    ++s.checked;
    if (cut[v]) s.worst_cut = std::max(s.worst_cut, error), ++s.cut;
  }
  return s;
}

// Across every cut edge the two sides have equal lengths, and the isometry taking one side's
// copy to the other's takes the next cut edge's copy along the same stretch of the cut to its
// counterpart. Returns the largest distance off, in the model's units (hyperbolic in the disk).
double gluing_error(const Delivered& d, int* cut_edges) {
  struct Side {
    int face, a, b;  // the face, and the corners of the edge's vertices v < w
  };
  std::map<std::pair<int, int>, std::vector<Side>> sides;
  const auto& faces = d.ply.faces;
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = faces[f][c], w = faces[f][(c + 1) % 3];
      sides[{std::min(v, w), std::max(v, w)}].push_back(
          {static_cast<int>(f), v < w ? c : (c + 1) % 3, v < w ? (c + 1) % 3 : c});
    }
  }
  struct Cut {
    Complex p0, p1, q0, q1;  // one side's copies of v and w, the other side's
    int model;
  };
  std::map<int, std::vector<Cut>> at_vertex;
  double worst = 0;
  *cut_edges = 0;
  for (const auto& [e, s] : sides) {
    if (s.size() != 2 || d.chart[s[0].face] != d.chart[s[1].face]) continue;
    const auto& x = d.corners[s[0].face];
    const auto& y = d.corners[s[1].face];
    const Cut c{x[s[0].a], x[s[0].b], y[s[1].a], y[s[1].b], d.model[s[0].face]};
    if (std::abs(c.p0 - c.q0) < 1e-9 && std::abs(c.p1 - c.q1) < 1e-9) continue;  // not cut
    ++*cut_edges;
    const double length = distance(c.model, c.p0, c.p1);
    worst = std::max(worst, std::abs(length - distance(c.model, c.q0, c.q1)));
    at_vertex[e.first].push_back(c);
    at_vertex[e.second].push_back({c.p1, c.p0, c.q1, c.q0, c.model});
  }
  // Two cut edges at one vertex whose copies there agree on both sides: the same isometry.
  for (const auto& [v, cuts] : at_vertex) {
    for (const Cut& c : cuts) {
      for (const Cut& o : cuts) {
        if (&c == &o || std::abs(c.p0 - o.p0) > 1e-9 || std::abs(c.q0 - o.q0) > 1e-9) continue;
        const Complex moved = move(c.model, c.p0, c.p1, c.q0, c.q1, o.p1);
        worst = std::max(worst, distance(c.model, moved, o.q1));
      }
    }
  }
  return worst;
}

// Angle sums at every interior vertex, those on the cut included: within 2e-9 (issue #33 asks
// 1e-8; measured 2026-12-04 from 5e-13 on the elephant to 7.1e-10 on the CAD part; before the
// development in long double and the narrower welding, tr12j was at 6.8e-9, polygon_mesh 3.0e-9).
constexpr double kAngleSumTolerance = 2e-9;

struct Case {
  std::string mesh;  // a real mesh (meshes/real-meshes.tsv) or CGAL's
  bool subdivided, charts;
  bool drawn_sides = false;  // the texture draws some new vertices on their faces' straight sides
};

// Twice the signed area of a triangle drawn with straight sides.
double drawn_orientation(Complex a, Complex b, Complex c) {
  return std::imag(std::conj(b - a) * (c - a));
}

// The Klein model's point of a Poincare disk point: geodesics are straight there, so a hyperbolic
// triangle's orientation is its Klein triangle's.
Complex klein(Complex z) {
  return 2.0 * z / (1.0 + std::norm(z));
}

std::ostream& operator<<(std::ostream& s, const Case& c) {
  return s << c.mesh;
}

std::string path_of(const std::string& mesh) {
  return mesh.find('.') != std::string::npos && mesh.rfind(".off") == mesh.size() - 4
             ? cgal(mesh)
             : std::string(RICCI_REAL_MESH_DIR) + "/" + mesh;
}

class PoincareLayout : public ::testing::TestWithParam<Case> {};

// Genus 6 and 22 after 549 and 8856 edge flips (common subdivisions cut open), genus 2 without
// flips, a genus-7 elephant with boundary drawn in 21 charts, a genus-12 printer model whose
// texture draws 338 corners of new vertices on straight sides, and a CAD part of genus 1 with 35
// boundary loops mapped on its double (11,815 flips), whose half reaches distance 14.4 and is
// drawn in 29 charts (developed across its pieces' sides, its angle sums were off by 7e-5), and
// CGAL's genus-4 polygon_mesh with 14 boundary loops after 6392 flips (developed breadth first in
// double, off by 5e-8 at its cut): every face is a positive
// hyperbolic triangle in the model and drawn positive in the texture, the angle sums hold to
// 1e-8 in the Poincare disk at the cut's vertices as everywhere, and the cut's sides glue.
TEST_P(PoincareLayout, AngleSumsHoldAndTheCutsSidesGlue) {
  const Case& c = GetParam();
  const Delivered d = run_and_read(path_of(c.mesh));
  ASSERT_FALSE(d.corners.empty());
  EXPECT_EQ(d.ply.has_vertex("ricci_input_face"), c.subdivided);
  int charts = 0;
  for (size_t f = 0; f < d.model.size(); ++f) {
    EXPECT_EQ(d.model[f], kDisk);
    charts = std::max(charts, d.chart[f] + 1);
    for (const Complex& z : d.corners[f]) ASSERT_LT(std::abs(z), 1.0);
  }
  EXPECT_EQ(charts > 1, c.charts);
  // Every face is a positive hyperbolic triangle in the model, and drawn positive in the texture.
  int turned_in_model = 0, turned_in_texture = 0;
  for (size_t f = 0; f < d.corners.size(); ++f) {
    const auto& z = d.corners[f];
    turned_in_model += !(drawn_orientation(klein(z[0]), klein(z[1]), klein(z[2])) > 0);
    const std::vector<double>& t = d.ply.face_texcoords_double[f];
    turned_in_texture +=
        !(drawn_orientation(Complex(t[0], t[1]), Complex(t[2], t[3]), Complex(t[4], t[5])) > 0);
  }
  EXPECT_EQ(turned_in_model, 0);
  EXPECT_EQ(turned_in_texture, 0);
  if (!c.charts) {
    // One chart: the texture coordinates are the disk's (z + 1) / 2, but where the texture draws
    // a new vertex on its face's straight side.
    int drawn = 0;
    for (size_t f = 0; f < d.corners.size(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const Complex uv = (d.corners[f][k] + Complex(1, 1)) / 2.0;
        const Complex texture(d.ply.face_texcoords_double[f][2 * k],
                              d.ply.face_texcoords_double[f][2 * k + 1]);
        if (std::abs(texture - uv) <= 1e-15) continue;
        ++drawn;
        EXPECT_GE(d.ply.vertex.at("ricci_input_face")[d.ply.faces[f][k]], 0)
            << "an input vertex drawn off its position";
      }
    }
    EXPECT_EQ(drawn > 0, c.drawn_sides) << drawn << " corners drawn on straight sides";
  }
  const Sums s = angle_sums(d);
  EXPECT_GT(s.checked, 0);
  EXPECT_LE(s.worst, kAngleSumTolerance) << s.checked << " interior vertices";
  if (!c.charts) {
    EXPECT_GT(s.cut, 0);
    EXPECT_LE(s.worst_cut, kAngleSumTolerance) << s.cut << " vertices on the cut";
    int cut_edges = 0;
    EXPECT_LE(gluing_error(d, &cut_edges), 1e-8);
    EXPECT_GT(cut_edges, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    RealMeshes, PoincareLayout,
    ::testing::Values(Case{"gmsh-lever.stl", true, false}, Case{"occt-tr12j.stl", true, false},
                      Case{"eight.off", false, false}, Case{"elephant-with-holes.off", true, true},
                      Case{"openscad-tardis.stl", true, false, true},
                      Case{"dart-wam6.STL", true, true}, Case{"polygon_mesh.off", true, false}),
    [](const auto& param_info) {
      std::string name = param_info.param.mesh.substr(0, param_info.param.mesh.find('.'));
      for (char& ch : name) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      }
      return name;
    });

// A flat torus (CGAL's knot1, genus 1): cut open in the plane, corner angles summing to 2 pi at
// every vertex, its sides glued by translations.
TEST(PlaneLayout, AFlatTorusAddsUpToTwoPiAndGluesAcrossTheCut) {
  const Delivered d = run_and_read(cgal("knot1.off"));
  ASSERT_FALSE(d.corners.empty());
  for (int m : d.model) EXPECT_EQ(m, kPlane);
  const Sums s = angle_sums(d);
  EXPECT_GT(s.cut, 0);
  EXPECT_LE(s.worst, 1e-8);
  int cut_edges = 0;
  double extent = 0;
  for (const auto& t : d.corners) {
    for (const Complex& z : t) extent = std::max(extent, std::abs(z));
  }
  EXPECT_LE(gluing_error(d, &cut_edges), 1e-8 * extent);
  EXPECT_GT(cut_edges, 0);
}

}  // namespace
}  // namespace ricci::test::cli
