#include "options.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <system_error>

#include "ricci/layout/packing.h"
#include "ricci/mesh/errors.h"

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

int parse_int(const std::string& flag, const std::string& text, int least = 0) {
  char* end = nullptr;
  errno = 0;
  const long x = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || x < least || x > 1000000) {
    throw InvalidArgumentError(flag + " expects an integer in [" + std::to_string(least) +
                               ", 1000000], got '" + text + "'");
  }
  return static_cast<int>(x);
}

std::string shortest(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

void set_target(Options& o, const std::string& spec) {
  o.target = spec;
  o.target_file.clear();
  for (const char* name : {"auto", "disk", "free-boundary", "zero", "atlas"}) {
    if (spec == name) {
      o.request.preset = target_preset_from_string(spec);
      return;
    }
  }
  o.request.preset = TargetPreset::Values;
  o.target_is_cones = spec.rfind("cones:", 0) == 0;
  o.target_file = o.target_is_cones ? spec.substr(6) : spec;
  if (o.target_file.empty()) throw InvalidArgumentError("--target cones: needs a file name");
  // A target that is no file: most likely a name mistyped (a usage error, as an unknown scheme).
  // (A name the file system cannot answer for, too long or behind a locked folder, is read as a
  // file, whose reading then says why.)
  std::error_code unknown;
  if (!o.target_is_cones && !std::filesystem::exists(spec, unknown) && !unknown) {
    throw InvalidArgumentError("--target '" + spec +
                               "' is no target (auto, disk, free-boundary, zero, atlas, "
                               "cones:FILE) and no file of Kbar values");
  }
}

// One flag: its names, its value's name (empty for a switch), its help (lines after the first
// are indented under it), the default shown (from a default Options), what it sets, and whether
// only --target atlas reads it (a usage error with any other target; its help begins "atlas: ").
struct Flag {
  std::vector<std::string> names;
  std::string value;
  std::string help;
  std::function<std::string(const Options&)> shown_default;
  std::function<void(Options&, const std::string& flag, const std::string& value)> set;
  bool atlas_only = false;
};

const std::vector<Flag>& flags() {
  using O = Options;
  static const std::vector<Flag> table = {
      {{"-o", "--output"},
       "FILE.ply",
       "result: per-vertex ricci_u, ricci_radius, ricci_curvature, ricci_target; layouts: "
       "layout_x/y/z per vertex (plane, sphere) and texture_u/v (plane), or per face corner "
       "texcoord (cut open, atlas); FILE.obj: positions, texture coordinates (vt) and faces",
       nullptr,
       [](O& o, const std::string&, const std::string& v) { o.output = v; }},
      {{"--geometry"},
       "G",
       "auto (by target and topology), euclidean, hyperbolic, spherical",
       [](const O& o) { return o.request.geometry ? to_string(*o.request.geometry) : "auto"; },
       [](O& o, const std::string&, const std::string& v) {
         if (v == "auto") {
           o.request.geometry.reset();
         } else {
           o.request.geometry = geometry_from_string(v);
         }
       }},
      {{"--scheme"},
       "S",
       "tangential, thurston, inversive-distance, yamabe, virtual-radius, mixed",
       [](const O& o) { return to_string(o.request.scheme.scheme); },
       [](O& o, const std::string&, const std::string& v) {
         o.request.scheme.scheme = scheme_from_string(v);
       }},
      {{"--angle"},
       "DEGREES",
       "Thurston's intersection angle, 0..90",
       [](const O& o) { return shortest(o.request.scheme.intersection_angle * 180 / kPi); },
       [](O& o, const std::string& f, const std::string& v) {
         o.request.scheme.intersection_angle = parse_double(f, v) * kPi / 180;
       }},
      {{"--eps"},
       "FILE",
       "mixed scheme: +1, 0 or -1 per line, one line per vertex",
       nullptr,
       [](O& o, const std::string&, const std::string& v) { o.eps_file = v; }},
      {{"--target"},
       "T",
       "the metric to reach\n"
       "  auto: by topology: closed genus 0 round sphere (S2), genus 1 flat torus (E2), genus >= 2 "
       "hyperbolic (H2); genus 0 with boundary the unit disk or a circle domain (E2); genus >= 1 "
       "with boundary H2 with geodesic boundary; best effort: where the circle domain gives no map "
       "the free boundary, where the Yamabe scheme gives none the tangential one (not with "
       "--no-flips or --keep-input-triangulation), with a warning\n"
       "  disk: boundary loops on circles, the outer one the unit circle\n"
       "  free-boundary: u = 0 on the boundary, flat inside\n"
       "  zero: Kbar = 0 at every vertex\n"
       "  atlas: a texture atlas of every topology: cones placed until the area distortion is "
       "within --distortion, the flat metric with u held at them (and on the boundary; at a "
       "cone budget that stops them above it, their curvatures of least distortion), seams "
       "through them on the mesh's edges, charts packed into [0, 1]^2\n"
       "  cones:FILE: lines \"VERTEX ANGLE_DEGREES\": corner angles on the boundary "
       "(rectangles, polygons); flat and straight elsewhere (cones inside: --target atlas "
       "--cones FILE)\n"
       "  FILE: Kbar per line, one line per vertex; 'nan' holds that vertex's u fixed; Kbar inside "
       "the surface (a cone) only where no layout is drawn (S2 on genus >= 1)",
       [](const O& o) { return o.target; },
       [](O& o, const std::string&, const std::string& v) { set_target(o, v); }},
      {{"--cones"},
       "FILE",
       "lines \"VERTEX ANGLE_DEGREES\" as for --target cones:FILE; with --target atlas the "
       "atlas's cones, with these angles, instead of placed ones (--distortion, --max-cones and "
       "--cone-angles then apply only to the parts of the mesh with none of them); alone the same "
       "as --target cones:FILE",
       nullptr,
       [](O& o, const std::string&, const std::string& v) { o.cones_file = v; }},
      {{"--distortion"},
       "D",
       "the area distortion to reach, sqrt(sum A (u - mean u)^2) on the surface scaled "
       "to area 1",
       [](const O& o) { return shortest(o.request.cone_placement.distortion_bound); },
       [](O& o, const std::string& f, const std::string& v) {
         o.request.cone_placement.distortion_bound = parse_double(f, v);
         if (!(o.request.cone_placement.distortion_bound > 0)) {
           throw InvalidArgumentError(f + " expects a positive number, got '" + v + "'");
         }
       },
       true},
      {{"--max-cones"},
       "N",
       "the most cones placed on each part (a closed genus-0 part takes at least 3)",
       [](const O&) { return std::to_string(kDefaultConeBudget); },
       [](O& o, const std::string& f, const std::string& v) {
         o.request.cone_placement.max_cones = max_cones_asked(parse_int(f, v, 1));
       },
       true},
      {{"--cone-angles"},
       "A",
       "free (as the flat metric wants them) or quarter (rounded to multiples of 90 "
       "degrees: charts that meet by quarter turns, but across loops around a handle or a hole)",
       [](const O& o) { return o.request.cone_placement.quarter_angles ? "quarter" : "free"; },
       [](O& o, const std::string& f, const std::string& v) {
         if (v != "free" && v != "quarter") {
           throw InvalidArgumentError(f + " expects free or quarter, got '" + v + "'");
         }
         o.request.cone_placement.quarter_angles = v == "quarter";
       },
       true},
      {{"--texture-size"},
       "N",
       "texels per side of the texture the charts are packed for",
       [](const O& o) { return std::to_string(o.request.packing.texture_size); },
       [](O& o, const std::string& f, const std::string& v) {
         o.request.packing.texture_size = parse_int(f, v, kMinTextureSize);
       },
       true},
      {{"--padding"},
       "N",
       "texels between two charts",
       [](const O& o) { return std::to_string(o.request.packing.padding); },
       [](O& o, const std::string& f, const std::string& v) {
         o.request.packing.padding = parse_int(f, v);
       },
       true},
      {{"--center"},
       "VERTEX",
       "disk target: the vertex mapped to the centre of the disk",
       nullptr,
       [](O& o, const std::string& f, const std::string& v) {
         o.request.center_vertex = parse_int(f, v);
       }},
      {{"--axis"},
       "VERTEX",
       "disk target: the vertex mapped onto the positive real axis",
       nullptr,
       [](O& o, const std::string& f, const std::string& v) {
         o.request.axis_vertex = parse_int(f, v);
       }},
      {{"--tolerance"},
       "X",
       "converged when max |K - Kbar| <= X, or, where double precision cannot reach X, when it "
       "is within 10 times the angle sums' round-off (the report says so)",
       [](const O& o) { return shortest(o.request.flow.tolerance); },
       [](O& o, const std::string& f, const std::string& v) {
         o.request.flow.tolerance = parse_double(f, v);
         if (!(o.request.flow.tolerance > 0)) throw InvalidArgumentError(f + " must be positive");
       }},
      {{"--max-iterations"},
       "N",
       "Newton iteration limit",
       [](const O& o) { return std::to_string(o.request.flow.max_iterations); },
       [](O& o, const std::string& f, const std::string& v) {
         o.request.flow.max_iterations = parse_int(f, v);
       }},
      {{"--solver"},
       "NAME",
       "sparse Cholesky: cholmod or ldlt (Eigen's SimplicialLDLT)",
       [](const O& o) { return to_string(o.request.flow.linear_solver); },
       [](O& o, const std::string&, const std::string& v) {
         o.request.flow.linear_solver = linear_solver_from_string(v);
       }},
      {{"--flips"},
       "WHEN",
       "edge flips that keep the triangulation (power) Delaunay: when-needed (on the input's "
       "triangulation until the flow cannot go on there, then with flips from where it stopped), "
       "always, never",
       [](const O& o) { return to_string(o.request.flow.edge_flips); },
       [](O& o, const std::string&, const std::string& v) {
         o.request.flow.edge_flips = edge_flips_from_string(v);
       }},
      {{"--no-flips"},
       "",
       "the same as --flips never: keep the input's triangulation",
       nullptr,
       [](O& o, const std::string&, const std::string&) {
         o.request.flow.edge_flips = EdgeFlips::Never;
       }},
      {{"--keep-input-triangulation"},
       "",
       "after edge flips, write the input's faces with their corners' layout even where they turn "
       "over (an error, as the layout is then no map) instead of the common subdivision (the "
       "input cut along the flipped triangulation's edges, with new vertices on its edges)",
       nullptr,
       [](O& o, const std::string&, const std::string&) {
         o.request.keep_input_triangulation = true;
       }},
      {{"--strict"},
       "",
       "refuse a mesh that needs repairs (by default duplicate, degenerate and misoriented faces, "
       "non-manifold edges and vertices are repaired in ways that keep the surface, and reported; "
       "each connected component is mapped on its own)",
       nullptr,
       [](O& o, const std::string&, const std::string&) { o.repair.strict = true; }},
      {{"--keep-cuts"},
       "",
       "keep vertices at one position apart: a mesh cut open (its vertices copied along the cut) "
       "stays cut (by default the ends of edges at the same two positions are joined, so that a "
       "triangle soup is one surface); the other repairs still apply",
       nullptr,
       [](O& o, const std::string&, const std::string&) { o.repair.join_coincident = false; }},
      {{"--report"},
       "FILE.json",
       "convergence history, timings and errors of the result",
       nullptr,
       [](O& o, const std::string&, const std::string& v) { o.report = v; }},
      {{"--picture"},
       "FILE.png",
       "picture of the planar layout (disks, circle domains)",
       nullptr,
       [](O& o, const std::string&, const std::string& v) { o.picture = v; }},
      {{"--ascii"},
       "",
       "write ASCII PLY instead of binary",
       nullptr,
       [](O& o, const std::string&, const std::string&) { o.ascii = true; }},
      {{"--quiet"},
       "",
       "no progress or summary output",
       nullptr,
       [](O& o, const std::string&, const std::string&) { o.quiet = true; }},
      {{"-h", "--help"},
       "",
       "this text",
       nullptr,
       [](O& o, const std::string&, const std::string&) { o.help = true; }},
      {{"--version"},
       "",
       "version",
       nullptr,
       [](O& o, const std::string&, const std::string&) { o.version = true; }},
  };
  return table;
}

const Flag* find_flag(const std::string& name) {
  for (const Flag& f : flags()) {
    for (const std::string& n : f.names) {
      if (n == name) return &f;
    }
  }
  return nullptr;
}

// Usage errors that need several flags together.
void check_combination(const Options& o) {
  if (!o.atlas_flag.empty() && o.request.preset != TargetPreset::Atlas) {
    throw InvalidArgumentError(o.atlas_flag + " is used only by --target atlas");
  }
  if (!o.cones_file.empty() && !o.target_file.empty()) {
    throw InvalidArgumentError("--cones " + o.cones_file + " and --target " + o.target +
                               ": give the cones once, with --target atlas or alone");
  }
  if (!o.cones_file.empty() && o.request.preset != TargetPreset::Atlas &&
      o.request.preset != TargetPreset::Automatic) {
    throw InvalidArgumentError("--cones " + o.cones_file + " with --target " + o.target +
                               ": the cones are a target of their own, or the atlas's cones");
  }
  if (!o.picture.empty() && o.request.preset == TargetPreset::Atlas) {
    throw InvalidArgumentError(
        "--picture draws a layout in the plane with one position per vertex, not an atlas's "
        "charts (its texture coordinates are in the output)");
  }
  if (o.request.scheme.scheme == Scheme::Mixed && o.eps_file.empty()) {
    throw InvalidArgumentError("the mixed scheme needs --eps FILE (+1, 0 or -1 per vertex)");
  }
  if (o.request.scheme.scheme != Scheme::Mixed && !o.eps_file.empty()) {
    throw InvalidArgumentError("--eps is used only by --scheme mixed");
  }
  check_scheme_options(o.request.scheme);
}

// The help's lines, each longer than `width` broken at spaces, continued with its own indent.
std::vector<std::string> wrapped(const std::string& text, size_t width) {
  std::vector<std::string> out;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const std::string indent(
        line.find_first_not_of(' ') == std::string::npos ? 0 : line.find_first_not_of(' '), ' ');
    while (line.size() > width && line.rfind(' ', width) != std::string::npos &&
           line.rfind(' ', width) > indent.size()) {
      const size_t cut = line.rfind(' ', width);
      out.push_back(line.substr(0, line.find_last_not_of(' ', cut) + 1));
      line = indent + "  " + line.substr(cut + 1);
    }
    out.push_back(line);
  }
  return out;
}

}  // namespace

std::string usage() {
  std::ostringstream s;
  s << "usage: ricci-flow INPUT -o OUTPUT.ply [options]\n\n"
       "Unified discrete surface Ricci flow (Zhang, Guo, Zeng, Luo, Yau, Gu): computes a metric "
       "of\n"
       "prescribed curvature conformal to the input mesh, and its layout: in the plane (UV), in\n"
       "the Poincare disk, or on the unit sphere.\n\n"
       "  INPUT                    mesh: .off .obj .ply .stl .gii (GIFTI surfaces; polygons are\n"
       "                           split into triangles as fans from their first corner); several\n"
       "                           components and dirty meshes are fine (see --strict)\n";
  const Options defaults;
  for (const Flag& f : flags()) {
    std::string head;
    for (const std::string& n : f.names) head += (head.empty() ? "" : ", ") + n;
    if (!f.value.empty()) head += " " + f.value;
    std::string help = (f.atlas_only ? "atlas: " : "") + f.help;
    if (f.shown_default) {
      help.insert(std::min(help.find('\n'), help.size()), "  [" + f.shown_default(defaults) + "]");
    }
    bool first = true;
    for (const std::string& line : wrapped(help, 66)) {
      std::string text = "  " + (first ? head : "");
      text.resize(std::max<size_t>(text.size(), 27), ' ');
      if (text.size() > 27) text += "\n" + std::string(27, ' ');
      s << text << line << "\n";
      first = false;
    }
  }
  return s.str();
}

Options parse_options(int argc, const char* const* argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (const Flag* flag = find_flag(a)) {
      std::string value;
      if (!flag->value.empty()) {
        if (i + 1 >= argc) throw InvalidArgumentError(a + " needs a value");
        value = argv[++i];
      }
      flag->set(o, a, value);
      if (flag->atlas_only && o.atlas_flag.empty()) o.atlas_flag = a;
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
  check_combination(o);
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
