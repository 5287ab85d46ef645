// The atlas preset (TargetPreset::Atlas) of one component: cones placed on the linear model
// (cone_placement.h), the exact flat metric with u held at them by the flow, and its layout on the
// user's surface:
//
//   delivered mesh   the input's faces, or where the flow flipped edges the common subdivision
//                    (its pieces are pieces of the flat metric's triangles, so each is drawn by its
//                    own side lengths: the discrete conformal map), unless the charts go back onto
//                    the user's faces (below)
//   seams            cut_through_cones (seams.h) on the delivered edges that lie on the user's
//                    edges, weighted by their 3D length; a cone's wedge past a full turn (its angle
//                    between two seams at it) is split by a branch from its middle
//   charts           lay_out_charts (charts.h); a chart whose faces overlap is split along a short
//                    path between the overlapping sheets and laid out again (the metric is flat:
//                    no new flow)
//   user's faces     a subdivision's charts moved onto the input's faces (charts_on_input), turned
//                    faces untangled, the insides drawn harmonic where that is needed: delivered
//                    where none of them turns over or overlaps, QC p95 is about the pieces' or
//                    lower and D within the bound: the user's mesh comes back with texture
//                    coordinates only; where some turn or overlap, those and the faces around
//                    them cut into their pieces (partly_cut_charts), the others the user's
//                    (drawn_where_deliverable, partly_cut_drawn: atlas_on_input.cpp)
//   packing          pack_atlas, once the attempt to deliver is chosen (packing.h); a component of
//                    a mesh of several is packed with the others instead (uniformize_mesh)
// Not installed API.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/flow/target.h"
#include "ricci/layout/charts.h"
#include "ricci/mesh/compact_mesh.h"
#include "ricci/pipeline/uniformization.h"
#include "ricci/subdivision/subdivided_mesh.h"

namespace ricci::detail {

//! The flow's target for placed cones: u held at the cones at 0 (or their curvature, where
//! `curvatures` asks for it or the placement's are those of least D, u free at the cones) and on
//! the boundary, Kbar = 0 at every other vertex.
TargetCurvature atlas_target(const CompactMesh& mesh, const ConePlacement& placement,
                             bool curvatures);

//! The cones that unfold the surface: every interior vertex whose angle sum in the input metric is
//! off 2 pi by more than `flat` (radians), at that angle sum, with u = 0. Their flat cone metric is
//! the input's own: it needs no flow step and no flip, and its atlas draws every face as its own
//! triangle (D 0), cut through all of them.
ConePlacement unfolding_cones(const CompactMesh& mesh, double flat);

//! Per edge of `delivered`, a common subdivision's triangulation of `mesh`: the edge of the
//! user's mesh it lies on (both ends on that input edge's closure), -1 where it lies on none.
std::vector<int> input_edge_under(const CompactMesh& mesh, const Triangulation& delivered,
                                  const CommonSubdivision& sub);
//! 1 per edge of `delivered` that lies on an edge of the user's mesh (input_edge_under), from
//! that mapping or computing it.
std::vector<char> on_input_edges(const std::vector<int>& under);
std::vector<char> on_input_edges(const CompactMesh& mesh, const Triangulation& delivered,
                                 const CommonSubdivision& sub);

//! A common subdivision's charts on the user's faces: the seams as input edges, and per input face
//! its chart and its corners as the pieces put them (the input's vertices are vertices of the
//! subdivision; a chart's border runs straight between them). Empty where a seam runs inside an
//! input face, or along part of an input edge only, or an input face's pieces lie in two charts.
struct InputCharts {
  std::vector<char> seam;  //!< per input edge
  Charts charts;           //!< per input face
};
//! `under`: input_edge_under of `delivered`.
std::optional<InputCharts> charts_on_input(const CompactMesh& mesh, const CommonSubdivision& sub,
                                           const Triangulation& delivered,
                                           const std::vector<int>& under,
                                           const std::vector<char>& seam, const Charts& charts);

//! The user's faces with those marked in `cut_up` (per input face) replaced by their pieces:
//! a coarser common subdivision of the same charts. Conforming where no input edge between a
//! marked and an unmarked face is split by a new vertex (pieces_closure). `pieces`: the
//! common subdivision's charts (per face of `delivered`, whose seams are `seam`), `in` those
//! moved onto the user's faces (charts_on_input).
struct PartlyCutCharts {
  //! The delivered faces in the input's order, a cut face's pieces in its place (a cut face of
  //! one piece is its own face); the input's vertices first, in order.
  CommonSubdivision sub;
  Triangulation delivered;  //!< of sub.faces
  std::vector<char> seam;   //!< per edge of `delivered`
  Charts charts;            //!< per delivered face, as developed
  int input_faces_cut = 0;  //!< the input faces delivered as more than one piece
};
PartlyCutCharts partly_cut_charts(const CompactMesh& mesh, const CommonSubdivision& sub,
                                  const Triangulation& delivered, const std::vector<char>& seam,
                                  const Charts& pieces, const InputCharts& in,
                                  const std::vector<char>& cut_up);

//! The input faces to cut into pieces so that `faces` are: they, and every input face across an
//! input edge of theirs that a new vertex of the subdivision splits (more than one delivered
//! edge `under` it), until none is. Per input face.
std::vector<char> pieces_closure(const CompactMesh& mesh, const std::vector<int>& under,
                                 const std::vector<int>& faces);

//! D and the 95th percentile of QC of faces as drawn.
struct AsDrawn {
  double distortion, qc_p95;
};
//! The 95th percentile of the quasi-conformal ratio of `faces` drawn with `corners`.
double qc_p95(const std::vector<Eigen::Vector3d>& positions,
              const std::vector<std::array<int, 3>>& faces,
              const std::vector<std::array<Eigen::Vector2d, 3>>& corners);

//! Charts drawn on faces other than the pieces', with how many of them were drawn harmonic inside
//! and how many wedges moved off turned faces.
struct Drawn {
  Charts charts;
  int redrawn = 0, untangled = 0;
};
//! Charts as developed on the pieces, moved onto other faces `t` (the user's, or the user's with
//! some cut into their pieces), drawn where no face turns over or overlaps another of its chart
//! and D is within `bound` or about the pieces' (see atlas_on_input.cpp for when their insides are
//! drawn harmonic). Where not given, `stuck` gets the faces that stay turned or overlap another.
std::optional<Drawn> drawn_where_deliverable(const Triangulation& t,
                                             const std::vector<Eigen::Vector3d>& positions,
                                             const std::vector<char>& seam, Charts charts,
                                             double bound, const AsDrawn& pieces,
                                             std::vector<int>& stuck);
//! The atlas delivered on the user's faces, with those around the `stuck` ones (that turned or
//! overlapped there) cut into their pieces (partly_cut_charts), in rounds that cut more while that
//! does not deliver; none where its QC p95 is far above the pieces' or too many faces are cut.
std::optional<std::pair<PartlyCutCharts, Drawn>> partly_cut_drawn(
    const CompactMesh& mesh, const CommonSubdivision& sub, const Triangulation& delivered,
    const std::vector<int>& under, const std::vector<char>& seam, const Charts& developed,
    const InputCharts& in, double bound, const AsDrawn& pieces, std::vector<int> stuck);

//! A common subdivision's charts (as developed on its pieces) delivered on the user's faces: all
//! of them (`user`), else with some cut into their pieces (`partly`), else neither (the pieces
//! are delivered then). Measured against the pieces as developed (AsDrawn).
struct OnInput {
  std::optional<InputCharts> in;
  std::optional<Drawn> user;
  std::optional<std::pair<PartlyCutCharts, Drawn>> partly;
};
OnInput delivered_on_input(const CompactMesh& mesh, const CommonSubdivision& sub,
                           const Triangulation& delivered, const std::vector<int>& under,
                           const std::vector<char>& seam, const Charts& charts, double bound);

//! Per edge of `delivered`, its length in 3D between `positions` (seams are shortest there).
std::vector<double> lengths_in_3d(const Triangulation& delivered,
                                  const std::vector<Eigen::Vector3d>& positions);

//! The atlas layout of a converged flow: run.corners (z = 0), run.face_chart, run.subdivision
//! where the flow flipped edges and the charts stay on it or some of the user's faces are cut into
//! their pieces (run.atlas.input_faces_cut; not where run.atlas.on_input_faces), run.atlas;
//! run.layout holds the delivered corners. Not packed: run.atlas.texture is empty and its
//! utilization and padding NaN until pack_atlas.
void lay_out_atlas(const CompactMesh& mesh, const UniformizationOptions& o, Uniformization& run);

//! An atlas run's charts packed into [0, 1]^2 (pack_charts; in quarter turns only where its
//! charts meet so, AtlasResult::quarter_turns): run.atlas.texture, utilization, padding. Nothing
//! where the run has no atlas layout or is packed already.
void pack_atlas(const PackingOptions& o, Uniformization& run);

//! The area distortion D of laid-out faces, as an independent check of an atlas measures it: with
//! A the 3D and a the layout's area of each face, both scaled to sum 1 over the faces where both
//! are positive (the others have no weight), s = log(a / A) / 2 and D = sqrt(sum A (s - mean
//! s)^2). The layout at one scale, any.
double face_distortion(const std::vector<Eigen::Vector3d>& positions,
                       const std::vector<std::array<int, 3>>& faces,
                       const std::vector<std::array<Eigen::Vector2d, 3>>& corners);

//! Why a converged atlas is no valid atlas (no layout, faces overlapping), or "".
std::string atlas_failure(const Uniformization& run);

}  // namespace ricci::detail
