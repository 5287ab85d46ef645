#include "filter_settings.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <utility>

#include "ricci/layout/packing.h"
#include "ricci/mesh/errors.h"

namespace ricci::plugin {

namespace {

using Kind = ParameterSpec::Kind;

const std::vector<Scheme> kSchemes = {Scheme::Tangential,        Scheme::Thurston,
                                      Scheme::InversiveDistance, Scheme::Yamabe,
                                      Scheme::VirtualRadius,     Scheme::Mixed};

int enum_index(const ParameterValues& values, const ParameterSpec& spec) {
  const auto it = values.find(spec.name);
  const double v = it == values.end() ? spec.default_value : it->second;
  const int n = static_cast<int>(spec.enum_labels.size());
  if (!(v >= 0 && v < n) || v != std::floor(v)) {
    throw InvalidArgumentError("parameter '" + spec.name + "': choice " + std::to_string(v) +
                               " is not one of the " + std::to_string(n) + " options");
  }
  return static_cast<int>(v);
}

const ParameterSpec& spec(const std::string& name) {
  for (const auto& s : parameter_specs()) {
    if (s.name == name) return s;
  }
  throw InvalidArgumentError("no parameter named '" + name + "'");
}

double number(const ParameterValues& values, const std::string& name) {
  const auto it = values.find(name);
  return it == values.end() ? spec(name).default_value : it->second;
}

int index_of(Scheme scheme) {
  return static_cast<int>(std::find(kSchemes.begin(), kSchemes.end(), scheme) - kSchemes.begin());
}

}  // namespace

const std::vector<ParameterSpec>& parameter_specs() {
  const FilterSettings d;
  static const std::vector<ParameterSpec> specs = {
      {"geometry",
       Kind::Enum,
       static_cast<double>(d.geometry),
       {"Auto by topology", "Euclidean (E2)", "Hyperbolic (H2)", "Spherical (S2)"},
       "Background geometry",
       "Geometry of the triangles of the result. Auto: the target's (for the Auto target: "
       "spherical for a closed genus-0 surface, Euclidean for a torus and for genus 0 with "
       "boundary, hyperbolic for genus >= 2 and for genus >= 1 with boundary; for per-vertex "
       "targets the one Gauss-Bonnet admits)."},
      {"scheme",
       Kind::Enum,
       static_cast<double>(index_of(d.scheme)),
       {"Tangential circle packing", "Thurston circle packing", "Inversive distance circle packing",
        "Yamabe flow", "Virtual radius circle packing", "Mixed (eps per vertex)"},
       "Scheme",
       "How edge lengths depend on the conformal factor u. Yamabe, inversive distance and virtual "
       "radius start from the mesh's own metric; tangential and Thurston packings prescribe the "
       "circle pattern (always-valid triangles, robust on scans)."},
      {"thurstonAngle",
       Kind::Float,
       d.thurston_angle_degrees,
       {},
       "Thurston intersection angle (degrees)",
       "Angle Phi in [0, 90] at which neighbouring circles intersect; eta = cos(Phi). Used by the "
       "Thurston scheme only."},
      {"mixedEps",
       Kind::Enum,
       static_cast<double>(d.mixed_eps),
       {"Selected vertices +1, others 0", "Sign of vertex quality (+1, 0, -1)"},
       "Mixed scheme: eps from",
       "Where the mixed scheme takes each vertex's eps: +1 circle packing, 0 Yamabe, -1 virtual "
       "radius."},
      {"target",
       Kind::Enum,
       static_cast<double>(d.target),
       {"Auto by topology (uniformization)", "Free boundary", "Zero curvature everywhere",
        "Per vertex from vertex quality", "Unit disk / circle domain",
        "Texture atlas: UV charts for any mesh, closed ones too"},
       "Target curvature",
       "Auto: round sphere (closed genus 0), flat torus (genus 1), hyperbolic metric (genus >= 2, "
       "geodesic boundary when it has one), unit disk (a disk) or circle domain (genus 0 with "
       "several boundaries); best effort: where the circle domain gives no map the free boundary, "
       "where the Yamabe scheme gives none the tangential one (not without edge flips or keeping "
       "the mesh's own faces), with a warning in the log. Unit "
       "disk: boundary loops on circles, the outer one the unit circle. "
       "Free boundary: u = 0 on the boundary (its lengths kept), flat inside: least area "
       "distortion. Zero: Kbar = 0 at every vertex. Vertex quality: Kbar in radians per vertex; "
       "NaN holds that vertex's u fixed; nonzero inside the surface (a cone) is refused where a "
       "layout is drawn, which a cone inside would not close."},
      {"centerVertex",
       Kind::Int,
       static_cast<double>(d.center_vertex),
       {},
       "Unit disk: center vertex",
       "Unit disk target (or Auto on a disk or circle domain): the index of the interior vertex "
       "mapped to the centre of the disk, by a Moebius map of the disk; -1: none."},
      {"axisVertex",
       Kind::Int,
       static_cast<double>(d.axis_vertex),
       {},
       "Unit disk: axis vertex",
       "Unit disk target: the index of the vertex turned onto the positive real axis (u axis of "
       "the UVs); -1: none."},
      {"tolerance",
       Kind::Float,
       d.tolerance,
       {},
       "Tolerance",
       "Converged when max |K - Kbar| <= this."},
      {"maxIterations",
       Kind::Int,
       static_cast<double>(d.max_iterations),
       {},
       "Iteration limit",
       "Newton iterations at most."},
      {"linearSolver",
       Kind::Enum,
       d.linear_solver == LinearSolverKind::Cholmod ? 0.0 : 1.0,
       {"CHOLMOD (supernodal Cholesky)", "Eigen SimplicialLDLT"},
       "Linear solver",
       "Sparse Cholesky used for the Newton steps."},
      {"maxStepHalvings",
       Kind::Int,
       static_cast<double>(d.max_step_halvings),
       {},
       "Step control: max halvings",
       "Line search: a Newton step is halved at most this many times to keep every triangle valid "
       "and reduce the curvature error."},
      {"edgeFlips",
       Kind::Bool,
       d.edge_flips ? 1.0 : 0.0,
       {},
       "Edge flips (keep the triangulation Delaunay)",
       "On: flip edges to keep the triangulation (power) Delaunay once the flow cannot go on on "
       "the "
       "mesh's own triangulation, from where it stopped. Off: never flip."},
      {"alwaysFlip",
       Kind::Bool,
       d.always_flip ? 1.0 : 0.0,
       {},
       "Always flip (Delaunay from the start)",
       "With edge flips on: keep the triangulation (power) Delaunay from the first step, even "
       "where "
       "the mesh's own triangulation would converge."},
      {"writeUV",
       Kind::Bool,
       d.write_texture_coordinates ? 1.0 : 0.0,
       {},
       "Write UV (texture coordinates)",
       "Store a planar layout as texture coordinates in [0,1]^2: per vertex for a disk or circle "
       "domain; per wedge (face corner) for surfaces cut open (torus, Poincare disk)."},
      {"writeQuality",
       Kind::Bool,
       d.write_quality ? 1.0 : 0.0,
       {},
       "Vertex quality = u, with color ramp",
       "Store the conformal factor u as vertex quality and color the mesh by it."},
      {"strictMesh",
       Kind::Bool,
       d.repair.strict ? 1.0 : 0.0,
       {},
       "Refuse meshes that need repairs",
       "Off (default): copies of a vertex along an edge (a triangle soup), duplicate, "
       "degenerate and misoriented faces, non-manifold edges and vertices are repaired in ways "
       "that keep the surface (the log says what was done; the "
       "mesh's faces are rebuilt then), and every connected component is mapped by its own "
       "topology. On: such a mesh is refused and left as it was."},
      {"keepCuts",
       Kind::Bool,
       d.repair.join_coincident ? 0.0 : 1.0,
       {},
       "Keep cuts (vertices at one position apart)",
       "Off (default): where edges of faces end at the same two positions, their vertices are "
       "joined, so that a triangle soup, or a mesh split along its hard edges, is one surface. "
       "On: the mesh's own connectivity is kept, and a mesh cut open (its vertices copied along "
       "the cut) stays cut; the other repairs still apply."},
      {"keepInputTriangulation",
       Kind::Bool,
       d.keep_input_triangulation ? 1.0 : 0.0,
       {},
       "Keep the mesh's own triangulation",
       "Off (default): when edge flips were needed and the mesh's own faces, drawn by their "
       "corners, would turn over, the mesh is replaced by the common subdivision (its faces cut "
       "along the flipped triangulation's edges; its vertices first and unchanged, new vertices on "
       "its edges), whose layout turns no face over. On: keep the mesh's faces; the filter then "
       "fails with the count of turned faces."},
      {"atlasDistortion",
       Kind::Float,
       d.atlas_distortion,
       {},
       "Texture atlas: area distortion bound",
       "Cones are added until D = sqrt(sum A (u - mean u)^2), on the surface scaled to area 1, is "
       "at most this: 0.2 keeps most texels within a factor 1.5 of the mean density; smaller "
       "takes more cones and charts."},
      {"atlasMaxCones",
       Kind::Int,
       static_cast<double>(d.atlas_max_cones),
       {},
       "Texture atlas: most cones",
       "The cone budget; the log warns when it stops the placement before the bound, and the "
       "cones then take the angles of least distortion."},
      {"atlasQuarterAngles",
       Kind::Bool,
       d.atlas_quarter_angles ? 1.0 : 0.0,
       {},
       "Texture atlas: cone angles in quarter turns",
       "Round every cone angle to a multiple of 90 degrees (charts then meet by quarter turns, "
       "as seamless textures and quad meshing want; on a surface of higher genus not across its "
       "loops around handles)."},
      {"atlasTextureSize",
       Kind::Int,
       static_cast<double>(d.atlas_texture_size),
       {},
       "Texture atlas: texture size (texels)",
       "Texels per side of the texture the charts are packed for; the padding is in these."},
      {"atlasPadding",
       Kind::Int,
       static_cast<double>(d.atlas_padding),
       {},
       "Texture atlas: padding (texels)",
       "Texels between two charts (half of it at the square's sides), against bleeding when the "
       "texture is filtered."},
      {"layoutLayer",
       Kind::Bool,
       d.add_layout_layer ? 1.0 : 0.0,
       {},
       "Add a layer with the layout",
       "Add a new mesh layer whose vertices are at the layout: the plane (z = 0) for disks and "
       "circle domains, the unit sphere for genus 0 in spherical geometry."},
  };
  return specs;
}

FilterSettings settings_from_values(const ParameterValues& values) {
  for (const auto& [name, value] : values) spec(name);  // unknown names are a programming error
  FilterSettings s;
  s.geometry = static_cast<GeometryChoice>(enum_index(values, spec("geometry")));
  s.scheme = kSchemes[enum_index(values, spec("scheme"))];
  s.thurston_angle_degrees = number(values, "thurstonAngle");
  s.mixed_eps = static_cast<MixedEpsSource>(enum_index(values, spec("mixedEps")));
  s.target = static_cast<TargetChoice>(enum_index(values, spec("target")));
  s.tolerance = number(values, "tolerance");
  if (!(s.tolerance > 0)) {
    throw InvalidArgumentError("parameter 'tolerance' must be positive, got " +
                               std::to_string(s.tolerance));
  }
  const double iterations = number(values, "maxIterations");
  const double halvings = number(values, "maxStepHalvings");
  if (!(iterations >= 0 && iterations <= 1e6) || !(halvings >= 0 && halvings <= 200)) {
    throw InvalidArgumentError(
        "parameters 'maxIterations' (0..1000000) and 'maxStepHalvings' "
        "(0..200) are out of range");
  }
  for (const auto& [name, vertex] :
       {std::pair{"centerVertex", &s.center_vertex}, std::pair{"axisVertex", &s.axis_vertex}}) {
    const double v = number(values, name);
    if (!(v >= -1) || v != std::floor(v)) {
      throw InvalidArgumentError(std::string("parameter '") + name +
                                 "' is a vertex index, or -1 for none; got " + std::to_string(v));
    }
    *vertex = static_cast<int>(v);
  }
  s.max_iterations = static_cast<int>(iterations);
  s.max_step_halvings = static_cast<int>(halvings);
  s.linear_solver = enum_index(values, spec("linearSolver")) == 0 ? LinearSolverKind::Cholmod
                                                                  : LinearSolverKind::Ldlt;
  s.edge_flips = number(values, "edgeFlips") != 0;
  s.always_flip = number(values, "alwaysFlip") != 0;
  s.write_texture_coordinates = number(values, "writeUV") != 0;
  s.write_quality = number(values, "writeQuality") != 0;
  s.add_layout_layer = number(values, "layoutLayer") != 0;
  s.repair.strict = number(values, "strictMesh") != 0;
  s.repair.join_coincident = number(values, "keepCuts") == 0;
  s.keep_input_triangulation = number(values, "keepInputTriangulation") != 0;
  s.atlas_distortion = number(values, "atlasDistortion");
  const double cones = number(values, "atlasMaxCones"), size = number(values, "atlasTextureSize"),
               padding = number(values, "atlasPadding");
  if (!(s.atlas_distortion > 0) || !(cones >= 1 && cones <= 1e6) ||
      !(size >= kMinTextureSize && size <= 1e6) || !(padding >= 0 && padding <= 1e4)) {
    throw InvalidArgumentError(
        "texture atlas parameters out of range: the distortion bound must be positive, the most "
        "cones 1..1000000, the texture size " +
        std::to_string(kMinTextureSize) + "..1000000 texels, the padding 0..10000 texels");
  }
  s.atlas_max_cones = static_cast<int>(cones);
  s.atlas_texture_size = static_cast<int>(size);
  s.atlas_padding = static_cast<int>(padding);
  s.atlas_quarter_angles = number(values, "atlasQuarterAngles") != 0;
  return s;
}

std::string filter_name() {
  return "Ricci Flow: Conformal Parameterization";
}

std::string filter_info() {
  return "Computes a discrete metric of prescribed curvature that is conformal to the mesh, by "
         "Newton's method on the Ricci energy, and its layout: in the plane (UV), in the Poincare "
         "disk, or on the unit sphere. One "
         "algorithm for 3 background geometries x 6 schemes, after M. Zhang, R. Guo, W. Zeng, "
         "F. Luo, S.-T. Yau and X. Gu, <i>The Unified Surface Ricci Flow</i>.<br><br>"
         "<b>Which scheme:</b> <i>Yamabe</i> (default) keeps the mesh's own conformal structure "
         "and suits smooth, well-shaped meshes; <i>inversive distance</i> and <i>virtual "
         "radius</i> also start from the mesh's metric; <i>tangential</i> and <i>Thurston</i> "
         "circle packings always keep valid triangles and converge on rough scans, at the price "
         "of a prescribed circle pattern; <i>mixed</i> takes eps per vertex (selection or quality "
         "sign).<br><br>"
         "<b>Results:</b> per-vertex attributes ricci_u, ricci_radius, ricci_curvature, "
         "ricci_target and, for layouts one point per vertex (disk, circle domain, sphere), "
         "ricci_layout; vertex quality = u with a color ramp; vertex texture coordinates for disks "
         "and circle domains, wedge texture coordinates for surfaces cut open (torus in the plane, "
         "higher genus in the Poincare disk).<br><br>"
         "<b>For a texture of any mesh,</b> closed ones too, choose the target <i>Texture "
         "atlas</i>: cones placed until the area distortion is within the bound, seams through "
         "them on the mesh's edges, charts without overlap packed into [0,1]^2 as wedge texture "
         "coordinates; the cones become the vertex selection.<br><br>"
         "<b>Meshes as they come:</b> triangle soups, duplicate, degenerate and misoriented "
         "faces, non-manifold edges and vertices are repaired in ways that keep the surface, and "
         "each connected component is mapped by its own topology (see <i>Refuse meshes that need "
         "repairs</i> and <i>Keep cuts</i>). The log reports the repairs and the layout's "
         "quality. A mesh that cannot be used (not orientable, no convergence, a layout with "
         "faces turned over) is left unchanged and the log says why.";
}

std::string python_filter_name() {
  return "compute_texcoord_parametrization_ricci_flow";
}

std::string python_parameter_name(const std::string& script_name) {
  std::string out;
  for (size_t i = 0; i < script_name.size(); ++i) {
    const char c = script_name[i];
    const bool upper = std::isupper(static_cast<unsigned char>(c)) != 0;
    if (upper && i > 0 && std::islower(static_cast<unsigned char>(script_name[i - 1]))) {
      out += '_';
    }
    out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

}  // namespace ricci::plugin
