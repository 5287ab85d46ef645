// What a uniformization is asked (UniformizationOptions) and what it delivers (Uniformization):
// the flow's result, its layout and the delivered mesh's positions, corners and quality
// (uniformize.h runs it).
#pragma once

#include <array>
#include <complex>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/cone_placement.h"
#include "ricci/flow/flow_result.h"
#include "ricci/flow/presets.h"
#include "ricci/layout/layout.h"
#include "ricci/layout/packing.h"
#include "ricci/linear/vertex_order.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/pipeline/layout_quality.h"
#include "ricci/subdivision/common_subdivision.h"

namespace ricci {

enum class LayoutKind {
  None,          //!< no layout (S2 with a cut)
  Plane,         //!< one position per vertex in the plane (disks, circle domains)
  PlaneCut,      //!< E2 cut open: wedge positions
  PoincareDisk,  //!< H2 cut open: wedge positions in the unit disk
  Sphere,        //!< one position per vertex on the unit sphere
  Atlas,         //!< E2 cone metric cut along seams into charts: wedge positions per chart
};
//! "none", "plane", "plane-cut", "poincare-disk", "sphere", "atlas".
std::string to_string(LayoutKind k);

struct UniformizationOptions {
  TargetPreset preset = TargetPreset::Automatic;
  //! The geometry; empty: the preset's (preset_geometry), or for Values the one Gauss-Bonnet
  //! admits (geometry_for_target).
  std::optional<Geometry> geometry;
  //! Values: Kbar per vertex, NaN where u stays fixed.
  Eigen::VectorXd values;
  //! Values given as cones instead (cone_target: flat and straight elsewhere); not empty: the
  //! preset is Values and `values` is ignored.
  std::vector<Cone> cones;
  SchemeOptions scheme;
  //! The flow's options, edge flips among them (when needed by default).
  FlowOptions flow;
  //! Disk preset: the vertex mapped to the centre of the unit disk, and the one mapped onto the
  //! positive real axis (-1: none).
  int center_vertex = -1, axis_vertex = -1;
  //! Disk preset: the boundary curvature is re-fitted to the boundary's current lengths until it
  //! changes by less than this (radians).
  double boundary_tolerance = 1e-9;
  //! The most flows of one run of repeated flows (there can be two: without flips, then with).
  int max_boundary_iterations = 200;
  //! After edge flips, lay out the input's own faces by their corners even when some turn over
  //! (reported as an invalid layout) instead of delivering the common subdivision.
  bool keep_input_triangulation = false;
  //! The atlas preset: how its cones are placed, and its charts packed.
  ConePlacementOptions cone_placement;
  PackingOptions packing;
  //! The atlas halves a long chart (a tube's strip) across its long axis where its component's
  //! charts packed alone fill the square fuller by a tenth. uniformize_mesh leaves it off for a
  //! component of less than 1/32 of the mesh's area, whose charts are small among the others'.
  bool halve_long_charts = true;
  //! The atlas gives up on a common subdivision of more than this many faces per input face (0:
  //! no bound), before its charts are cut and drawn: its attempt with loops (the last) does not
  //! spend minutes on cones of many turns whose pieces cross each input face dozens of times.
  int max_pieces_per_face = 0;
  //! A fill-reducing order of the vertices, found ahead (vertex_order.h; for uniformize_mesh, of
  //! the input's vertices, as read); empty or for another number of vertices: the flow starts its
  //! own (RicciFlowSolver).
  VertexOrder vertex_order;
  //! Per vertex, its number in the user's mesh, for messages (uniformize_mesh sets it for each
  //! component); empty: the same numbers.
  std::vector<int> input_vertex;
};

//! Sums over the flows of one uniformization (the disk preset runs several).
struct FlowTotals {
  int flows = 0;
  int newton_iterations = 0;
  int edge_flips = 0;
  int symbolic_analyses = 0;
  int numeric_factorizations = 0;
  int krylov_iterations = 0;  //!< MINRES iterations (the disk preset's one-solve flow)
  //! EdgeFlips::WhenNeeded: the Newton iteration, counted over the flows, from which edge flips
  //! were on, and why the input's triangulation was not enough; -1 and "": never needed.
  int flips_from_iteration = -1;
  std::string without_flips;
  //! The largest FlowResult::attainable_residual of the flows: 0 when each reached the tolerance.
  double attainable_residual = 0;
  FlowTimes times;
  void add(const FlowResult& r);
  void add(const FlowTotals& other);
};

//! What the atlas preset made: its cones, seams and charts.
struct AtlasResult {
  //! The placement; for the user's cones (UniformizationOptions::cones) only their vertices and
  //! angles, the linear model's figures NaN.
  ConePlacement placement;
  bool user_cones = false;  //!< the cones are the user's, not placed
  //! Why the surface is unfolded instead of cut at placed cones (bound_instead says more): a cone
  //! at every interior vertex of curvature, at its angle sum, whose flat metric is the input's own
  //! (no flow: D 0, each face its own shape), cut through them all; its seams are longer.
  enum class Unfolded {
    No,
    NoAtlas,        //!< no placed cones gave an atlas (the flow stalled, or the layout failed)
    MoreConformal,  //!< a coarse part whose placed cones left its faces far from conformal
    WithinBound,    //!< a part whose placed cones left its faces' D above the bound asked
  } unfolded = Unfolded::No;
  //! The distortion bound the cones were placed for (less the placement's 2 % margin): the one
  //! asked, or a tighter one where with the cones of the one asked the flow or the layout
  //! failed, or the delivered faces' D exceeded the bound asked (bound_instead says why).
  double bound = 0;
  std::string bound_instead;
  double bound_asked = 0;  //!< the bound the request asked for
  //! The flow's flips made edges from a vertex to itself (FlowOptions::loops): the first attempt
  //! without them wanted one (stalled for it, or ended with one refused), and no other attempt
  //! nor the unfolding gave an atlas.
  bool loops = false;
  //! The cones' curvatures are those of u = 0 at them where the budget stopped the placement above
  //! its bound: their curvatures of least D (ConePlacement::least_distortion) gave no atlas, or one
  //! far less conformal (bound_instead says which).
  bool held_curvatures = false;
  //! The charts are turned to meet by quarter turns (turn_charts_to_quarter_turns) and are packed
  //! in quarter turns only: placed cones rounded to them (--cone-angles quarter; the user's cones
  //! keep their own angles).
  bool quarter_turns = false;
  //! D of the flow's u (the exact flat metric) at the vertices, on the surface scaled to area 1.
  double flow_distortion = 0;
  //! D of the delivered faces: sqrt(sum A (s - mean s)^2), s = log(a / A) / 2, with A the 3D and
  //! a the chart area of each face, both scaled to sum 1 (what the bound is held to).
  double distortion = 0;
  //! The cones' angles in the exact metric (2 pi - K there, K from the flow), per placed cone.
  std::vector<double> cone_angles;
  int num_charts = 0;
  double seam_length = 0;  //!< in 3D, over sqrt(3D area)
  int seam_edges = 0;      //!< delivered edges on a seam
  //! Faces of a chart whose interiors overlap another face of the same chart.
  int overlapping_faces = 0;
  //! Charts split because they overlapped themselves, and the splits.
  int charts_split = 0, splits = 0;
  int halvings = 0;  //!< long charts halved across their long axis (for the packing)
  //! Charts whose inside is drawn as the harmonic map of their border (of a common subdivision,
  //! or moved onto the user's faces).
  int harmonic_charts = 0;
  //! The flow flipped edges, and the atlas is delivered on the user's faces all the same: its
  //! charts drawn on the common subdivision, then moved onto the input's faces (the input's
  //! vertices where the charts put them, but for those untangled or drawn harmonic inside), none
  //! of which turns over or overlaps (see pipeline/texture_atlas.h). The layout's
  //! max_relative_length_error is then still the charts' development's: the input's edges are
  //! drawn as chords, not at the metric's lengths.
  bool on_input_faces = false;
  //! Vertices moved (each towards the mean of its neighbours, the least way that turns its faces
  //! counter-clockwise) where the drawing on the input's faces, or on the common subdivision's
  //! pieces, turned a face over.
  int untangled = 0;
  //! Where the user's faces draw but for a few: the input faces delivered as more than one piece
  //! (around those that do not draw, a cone opening a corner past a half turn, out to input edges
  //! that no new vertex splits); the others are delivered as they are, and run.subdivision holds
  //! both. 0 where on_input_faces or all are pieces.
  int input_faces_cut = 0;
  //! Per delivered face corner, the charts packed into [0, 1]^2, and their share of its area.
  //! A component of several is not packed alone, nor is an atlas with no layout: this is empty
  //! and the utilization, padding and padding_asked NaN (a component's texture is then
  //! MeshUniformization's, its figures MeshUniformization::packed).
  std::vector<std::array<Eigen::Vector2d, 3>> texture;
  double utilization = 0;
  //! Texels between two charts at least, and the padding asked: less only where the charts are
  //! too many for the texture size at that padding (Packing::padding).
  double padding = 0, padding_asked = 0;
  int charts_below_a_texel = 0;  //!< Packing::below_a_texel
  //! Wall time of the stages after the flow: seams and charts with their overlap splits, the
  //! harmonic redrawing of the charts' insides, the packing (the halvings' packings and the
  //! delivered one; a component of several has only the former: the joint packing is
  //! MeshUniformization's).
  struct Seconds {
    double charts = 0, harmonic = 0, packing = 0;
  } seconds;
};

//! "no", "no-atlas", "more-conformal", "within-bound".
std::string to_string(AtlasResult::Unfolded u);

struct Uniformization {
  TargetPreset preset = TargetPreset::Automatic;  //!< the one used (never Automatic)
  Geometry geometry = Geometry::Euclidean;
  Scheme scheme = Scheme::Yamabe;
  double tolerance = 0;          //!< the flow's, on max |K - Kbar|
  ConformalStructure structure;  //!< the initial structure
  FlowResult result;             //!< the last flow
  FlowTotals totals;
  //! Wall time of the whole run (uniformize): every attempt's cone placement, flows, layouts and
  //! packings, the delivered attempt's stages (AtlasResult::seconds) among them.
  double seconds = 0;
  double boundary_change = 0;  //!< disk preset: last change of the boundary curvature
  double circle_error = 0;     //!< disk preset: max | |z - c| - r | / r over boundary loops

  LayoutKind layout_kind = LayoutKind::None;
  //! The layout of the flow's final triangulation (empty when the flow did not converge).
  Layout layout;
  //! Plane and Sphere: position per vertex (Plane: z = 0).
  std::vector<Eigen::Vector3d> position;
  //! Every layout: positions per face and corner of the delivered mesh (the input's, or the
  //! common subdivision's).
  std::vector<std::array<Eigen::Vector3d, 3>> corners;
  //! PoincareDisk where the drawing moved new vertices onto their faces' sides as drawn
  //! (CommonSubdivision::model_corners): per delivered face, the corners in the model, on the
  //! geodesics; `corners` are then the drawing (the texture's). Empty otherwise.
  std::vector<std::array<Eigen::Vector3d, 3>> model_corners;
  //! PoincareDisk laid out in several charts (Layout::chart), and Atlas: per delivered face, the
  //! chart its corners are in; empty for one chart.
  std::vector<int> face_chart;
  //! The mesh delivered instead of the input's: when the flow flipped edges and the input's faces
  //! drawn by their corners would turn over (common_subdivision.h) or be farther from conformal
  //! than its pieces (an atlas: or the input's faces with a few cut into their pieces,
  //! AtlasResult::input_faces_cut); when the Poincare disk's
  //! drawing split sides (disk_drawing.h) or needs charts (Layout::chart). `position` and
  //! `corners` are then its.
  std::optional<CommonSubdivision> subdivision;
  //! Input faces that turned over when drawn by their corners on the flipped triangulation.
  int input_faces_turned_over = 0;
  //! Where none turned over but the subdivision is delivered as the more conformal map: the
  //! quasi-conformal ratio p95 of the input's faces so drawn (NaN otherwise).
  double input_faces_qc_p95 = std::numeric_limits<double>::quiet_NaN();
  //! Sphere: the centring Moebius map was not applied because it would turn faces over.
  bool centring_skipped = false;
  //! The flow ran on the surface doubled along its boundary (doubled_surface.h), because on the
  //! surface itself triangles at the boundary stalled it, or it converged in a discrete conformal
  //! class other than the double's, the canonical one; `result` is the half's part of it.
  bool doubled = false;
  //! With `doubled`: why the flow on the surface itself stopped, or how its class differed.
  std::string doubled_because;
  //! Where the double was flowed but gave no result, why not: the surface's class was not its
  //! double's, or the disk's one solve stalled at the boundary's triangles (the surface's own
  //! result is delivered, where it has one); "" otherwise.
  std::string double_failure;
  //! Why the common subdivision could not be built, or "".
  std::string subdivision_failure;
  //! Flat torus (E2, closed genus 1): two translations spanning the period lattice, from the deck
  //! transformations; |Im(conj(w0) w1)| is the torus's area.
  std::vector<std::complex<double>> periods;
  LayoutQuality quality;  //!< of the delivered mesh's layout
  AtlasResult atlas;      //!< the atlas preset
  //! Why the layout is not a valid map (faces turned over, boundary off its circles), or "".
  std::string layout_failure;
  //! TargetPreset::Automatic: why the preset used is not the topology's choice, or "". A circle
  //! domain (UnitDisk) that is not reached, or whose layout is no map (faces squeezed below what
  //! double precision draws), gives way to FreeBoundary where that is valid.
  std::string target_instead;
  //! TargetPreset::Automatic with the Yamabe scheme: why the tangential scheme's run is delivered
  //! instead of the Yamabe flow's, which gave no valid map, or "".
  std::string scheme_instead;

  bool converged() const { return result.converged; }
  //! Converged, and the layout a valid map.
  bool valid() const { return converged() && layout_failure.empty(); }
  //! \throws ConvergenceError with flow_failure_message (naming `subject`, e.g. the input file,
  //!   when not empty) when the flow did not converge, LayoutError when the layout is invalid.
  void require_valid(const std::string& subject = "") const;
};

//! The kind of layout uniformize() gives for a resolved request, when the flow converges.
LayoutKind planned_layout(const Triangulation& mesh, TargetPreset preset, Geometry geometry);

//! The delivered faces' corners drawn in the plane (x, y): the layout's, except that a Poincare
//! disk layout in several charts has chart k's disk moved to its own place in a grid of disks
//! (row-major, 2.25 apart). Empty for the sphere and no layout.
std::vector<std::array<Eigen::Vector2d, 3>> drawn_corners(const Uniformization& run);

//! Texture coordinates in [0, 1]^2 of a layout: per vertex for Plane (scaled with the aspect ratio
//! kept), per face corner for PlaneCut (the same) and PoincareDisk ((z + 1) / 2 for one chart,
//! the grid of drawn_corners scaled like PlaneCut for several); none for the sphere.
struct TextureCoordinates {
  std::vector<Eigen::Vector2d> vertex;
  std::vector<std::array<Eigen::Vector2d, 3>> wedge;
};
TextureCoordinates texture_coordinates(const Uniformization& run);

}  // namespace ricci
