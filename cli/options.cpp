#include "options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "ricci/errors.h"

namespace ricci::cli {

namespace {

double parse_double(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(x)) {
    throw InvalidArgumentError(flag + " expects a finite number, got '" + text + "'");
  }
  return x;
}

int parse_int(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const long x = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || x < 0 || x > 1000000) {
    throw InvalidArgumentError(flag + " expects an integer in [0, 1000000], got '" + text + "'");
  }
  return static_cast<int>(x);
}

}  // namespace

std::string usage() {
  return R"(usage: ricci-flow INPUT -o OUTPUT.ply [options]

Unified discrete surface Ricci flow (Zhang, Guo, Zeng, Luo, Yau, Gu): computes a metric of
prescribed curvature conformal to the input mesh, and its layout: in the plane (UV), in the
Poincare disk, or on the unit sphere.

  INPUT                    mesh: .off .obj .ply .stl (one connected manifold triangle mesh)
  -o, --output FILE.ply    result: per-vertex ricci_u, ricci_radius, ricci_curvature,
                           ricci_target; layouts: layout_x/y/z per vertex (plane, sphere)
                           and texture_u/v (plane), or per face corner texcoord (cut open)
  --geometry G             auto (by target and topology), euclidean, hyperbolic,
                           spherical                                               [auto]
  --scheme S               tangential, thurston, inversive-distance, yamabe,
                           virtual-radius, mixed                                   [yamabe]
  --angle DEGREES          Thurston's intersection angle, 0..90                    [60]
  --eps FILE               mixed scheme: +1, 0 or -1 per line, one line per vertex
  --target T               the metric to reach                                      [auto]
                             auto: by topology: closed genus 0 round sphere (S2), genus 1
                               flat torus (E2), genus >= 2 hyperbolic (H2); genus 0 with
                               boundary the unit disk or a circle domain (E2); genus >= 1
                               with boundary H2 with geodesic boundary
                             disk: boundary loops on circles, the outer one the unit circle
                             free-boundary: u = 0 on the boundary, flat inside
                             zero: Kbar = 0 at every vertex
                             cones:FILE: lines "VERTEX ANGLE_DEGREES": cone angles inside,
                               corner angles on the boundary (rectangles, polygons); flat
                               and straight elsewhere
                             FILE: Kbar per line, one line per vertex; 'nan' holds that
                               vertex's u fixed
  --center VERTEX          disk target: the vertex mapped to the centre of the disk
  --axis VERTEX            disk target: the vertex mapped onto the positive real axis
  --tolerance X            converged when max |K - Kbar| <= X                      [1e-10]
  --max-iterations N       Newton iteration limit                                  [100]
  --solver cholmod|ldlt    sparse Cholesky: CHOLMOD or Eigen's SimplicialLDLT      [cholmod]
  --no-flips               keep the input triangulation (by default edges are flipped
                           to keep it (power) Delaunay, which real meshes need)
  --report FILE.json       convergence history, timings and errors of the result
  --picture FILE.png       picture of the planar layout (euclidean disks)
  --ascii                  write ASCII PLY instead of binary
  --quiet                  no progress or summary output
  -h, --help               this text
  --version                version
)";
}

Options parse_options(int argc, const char* const* argv) {
  Options o;
  auto value = [&](int& i, const std::string& flag) -> std::string {
    if (i + 1 >= argc) throw InvalidArgumentError(flag + " needs a value");
    return argv[++i];
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      o.help = true;
    } else if (a == "--version") {
      o.version = true;
    } else if (a == "-o" || a == "--output") {
      o.output = value(i, a);
    } else if (a == "--geometry") {
      o.geometry = value(i, a);
    } else if (a == "--scheme") {
      o.scheme = value(i, a);
    } else if (a == "--angle") {
      o.angle_degrees = parse_double(a, value(i, a));
    } else if (a == "--eps") {
      o.eps_file = value(i, a);
    } else if (a == "--target") {
      o.target = value(i, a);
    } else if (a == "--center") {
      o.center_vertex = parse_int(a, value(i, a));
    } else if (a == "--axis") {
      o.axis_vertex = parse_int(a, value(i, a));
    } else if (a == "--tolerance") {
      o.tolerance = parse_double(a, value(i, a));
      if (!(o.tolerance > 0)) throw InvalidArgumentError("--tolerance must be positive");
    } else if (a == "--max-iterations") {
      o.max_iterations = parse_int(a, value(i, a));
    } else if (a == "--solver") {
      o.solver = value(i, a);
    } else if (a == "--report") {
      o.report = value(i, a);
    } else if (a == "--picture") {
      o.picture = value(i, a);
    } else if (a == "--no-flips") {
      o.edge_flips = false;
    } else if (a == "--ascii") {
      o.ascii = true;
    } else if (a == "--quiet") {
      o.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw InvalidArgumentError("unknown option '" + a + "'; see ricci-flow --help");
    } else if (o.input.empty()) {
      o.input = a;
    } else {
      throw InvalidArgumentError("more than one input mesh given ('" + o.input + "', '" + a + "')");
    }
  }
  if (o.help || o.version) return o;
  if (o.input.empty()) throw InvalidArgumentError("no input mesh given; see ricci-flow --help");
  if (o.output.empty()) throw InvalidArgumentError("no output given: add -o OUTPUT.ply");
  return o;
}

std::vector<double> read_numbers(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError("cannot open '" + path + "'");
  std::vector<double> values;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto last = line.find_last_not_of(" \t\r");
    const std::string text = line.substr(first, last - first + 1);
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (*end != '\0') {
      throw IoError(path + ":" + std::to_string(number) + ": '" + text + "' is not a number");
    }
    values.push_back(x);
  }
  return values;
}

}  // namespace ricci::cli

namespace ricci::cli {

std::vector<std::pair<int, double>> read_cones(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError("cannot open cone file '" + path + "'");
  std::vector<std::pair<int, double>> cones;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    long vertex = -1;
    double degrees = 0;
    std::string rest;
    if (!(fields >> vertex >> degrees) || (fields >> rest) || vertex < 0) {
      throw IoError(path + ":" + std::to_string(number) + ": '" + line +
                    "' is not 'VERTEX ANGLE_DEGREES' (a vertex index and a cone angle)");
    }
    cones.emplace_back(static_cast<int>(vertex), degrees);
  }
  return cones;
}

}  // namespace ricci::cli
