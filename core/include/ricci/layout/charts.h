// The charts of a flat metric cut open along seams: every piece of the surface that the seams
// (and the boundary) leave connected across its edges, developed into the plane face by face.
// Where the seams pass through every cone, each chart is flat and its layout exact up to
// round-off; the corners of one vertex in a chart (its wedge) share one position.
#pragma once

#include <array>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ricci/mesh/triangulation.h"

namespace ricci {

struct Charts {
  std::vector<std::array<Eigen::Vector2d, 3>> corners;  //!< per face, in its chart's plane
  std::vector<int> chart;                               //!< per face
  int num_charts = 0;
  //! max | |x_head - x_tail| / l - 1 | over the faces' edges.
  double max_relative_length_error = 0;
  int flipped_faces = 0;  //!< faces of non-positive signed area
};

//! Develops each chart from its face deepest inside it (across uncut edges, the longest side that
//! joins a face to a placed one first, each face drawn from that side by triangle_apex), then puts
//! every wedge at the mean of its corners. `lengths` per edge, `cut` per edge (1: seam; boundary
//! edges need no mark).
Charts lay_out_charts(const Triangulation& mesh, const std::vector<double>& lengths,
                      const std::vector<char>& cut);
//! The same with each face's own side lengths (`sides[f][c]`: of mesh.face_edge(f, c)), for
//! pieces whose lengths of a shared edge differ by rounding (a common subdivision's, drawn piece
//! by piece): each face is placed by its own sides, so a sliver keeps its orientation; the
//! relative length error is measured against them.
Charts lay_out_charts(const Triangulation& mesh, const std::vector<std::array<double, 3>>& sides,
                      const std::vector<char>& cut);
//! The same with each face's own drawn corners (`drawn[f]`, anywhere in the plane): each face is
//! placed by the rigid motion that puts its side shared with the face it is reached from onto that
//! side as placed, so its angles stay its own; drawn from its side lengths instead, a sliver's
//! angles move by their rounding over its width. The seed keeps its drawn position.
Charts lay_out_charts(const Triangulation& mesh,
                      const std::vector<std::array<Eigen::Vector2d, 3>>& drawn,
                      const std::vector<char>& cut);

//! Turns each chart about the origin so that across every seam between two charts the two
//! drawings of an edge differ by a multiple of a quarter turn, as they do within a chart where
//! every cone's curvature is one (--cone-angles quarter): outwards from chart 0 over the charts'
//! seams, each chart turned so that it draws the longest side it shares with the chart it is
//! reached from along that chart's drawing. Seams across a loop of the surface around a handle or
//! a hole keep the turn the surface makes there. `faces`: the vertices of the faces drawn.
void turn_charts_to_quarter_turns(const std::vector<std::array<int, 3>>& faces, Charts& charts);

//! The signed area of a drawn face: positive where its corners run counter-clockwise.
double signed_area(const std::array<Eigen::Vector2d, 3>& t);

//! Per face corner (3 f + c), its wedge: a representative of the corners of its vertex that are
//! joined across uncut edges (the corners one position of a chart stands for).
std::vector<int> chart_wedges(const Triangulation& mesh, const std::vector<char>& cut);

//! Redraws the inside of every chart whose flag in `which` is set as the harmonic map of its
//! border as drawn: the wedges of the border (at a seam or a boundary edge) stay, the others go
//! where the cotangent Laplacian of the faces' 3D shapes (`positions`) vanishes, the map of least
//! conformal energy with that border. A chart keeps its drawing where the redrawn one turns a face
//! over, overlaps itself, or has a higher 95th percentile of quasi-conformal ratio than a drawing
//! with no face turned over, or a face of it has no 3D area. Returns the charts redrawn. The
//! charts' max_relative_length_error stays the development's: a redrawn inside leaves the metric's
//! lengths on purpose.
int draw_harmonic_insides(const Triangulation& mesh, const std::vector<Eigen::Vector3d>& positions,
                          const std::vector<char>& cut, const std::vector<char>& which,
                          Charts& charts);

//! Faces turned over in `charts` untangled: a wedge off the border of such a face moved towards
//! the mean of its neighbours, the least of 1/16, 1/8 .. 1 of the way that leaves every face
//! around it counter-clockwise (a vertex inside the kernel of its star has its faces all
//! counter-clockwise; the mean is there where the star is not far from convex), in a few rounds
//! over the faces still turned. A vertex inside a seam's path (two seam edges, a wedge on each
//! side, whose drawings one rotation relates to 1e-6 of the edges' lengths: no cone, but one of
//! whole turns) moves as one with its two wedges, towards the mean of its neighbours on both
//! sides, its second wedge by that rotation (the nearest to taking both edges of one side to the
//! other's), so that the seam's two sides stay congruent. A face whose corners are all at cones, at
//! branches or ends of seams, or on the boundary stays turned. Then each group of faces still
//! turned is redrawn with the faces within one to four rings of it: the wedges off the border
//! whose faces are all in that region at the mean of their neighbours in mean value weights of
//! their 3D stars (`positions`), the others held, kept at the first region where every face with
//! a wedge solved for turns counter-clockwise and one of them was turned (a face whose corners are
//! all held stays as it was). Returns the wedges moved (each by a corner of it; one per vertex).
//! `cut` as for lay_out_charts.
std::vector<int> untangle_turned_faces(const Triangulation& mesh,
                                       const std::vector<Eigen::Vector3d>& positions,
                                       const std::vector<char>& cut, Charts& charts);

//! The quasi-conformal ratio of a face's map from its 3D corners (`positions` at `face`) to its
//! drawing `corners`.
double drawn_quasi_conformal_ratio(const std::vector<Eigen::Vector3d>& positions,
                                   const std::array<int, 3>& face,
                                   const std::array<Eigen::Vector2d, 3>& corners);

//! Pairs of faces of one chart whose interiors overlap (beyond a relative tolerance of 1e-9 of
//! the chart's size): the whole chart tested, not only neighbours, through a hierarchy of the
//! faces' bounding boxes. Each pair once, smaller face first; at most max_pairs of them
//! (0: all). Of each chart, with `per_chart` (0: all), only its first pairs: its faces in order
//! until they make at least that many, the pairs of their smaller faces' order up to there.
//! Charts whose flag in `known_clean` is set are not tested.
std::vector<std::pair<int, int>> overlapping_faces(const Charts& charts, size_t max_pairs = 0,
                                                   const std::vector<char>& known_clean = {},
                                                   size_t per_chart = 0);

//! Per chart: 1 where its layout is an embedding for certain, so that overlapping_faces would find
//! no pair in it: the chart is a disk (Euler characteristic 1, one border loop through wedges
//! that each have one border side out and one in), every face counter-clockwise, every inner
//! wedge's angles summing to 2 pi (one turn), and its border a simple polygon, no two sides that
//! do not follow one another nearer than 1e-7 of its size (a locally injective map of a disk
//! whose border is a simple closed curve is injective). Linear in the chart's faces plus its
//! border's sides times their log, where the whole test pairs every face with its neighbours in
//! a hierarchy. `cut` as for lay_out_charts, and the charts laid out with it.
std::vector<char> embedded_charts(const Triangulation& mesh, const std::vector<char>& cut,
                                  const Charts& charts);

//! overlapping_faces for charts laid out with `cut`, of which those embedded for certain
//! (embedded_charts) are not tested either: the same pairs, found sooner.
std::vector<std::pair<int, int>> overlapping_faces(const Triangulation& mesh,
                                                   const std::vector<char>& cut,
                                                   const Charts& charts,
                                                   std::vector<char> known_clean = {},
                                                   size_t per_chart = 0);

//! How deep faces f and g of a layout overlap, relative to the smaller: how far their interiors
//! reach into each other (the least over the six side directions) over the shorter of their
//! longest sides; <= 0 where they do not overlap. Pieces of a common subdivision that disagree on
//! a side by rounding can overlap by a sliver's width in one layout and not in another.
double overlap_depth(const Charts& charts, int f, int g);

//! Per chart of `now`: 1 where it is a chart of `before` without any of the overlapping pairs
//! `before_overlaps`, laid out the same (its faces, at the same corners): a chart that need not be
//! tested for overlaps again. Both layouts of one mesh; `before_overlaps` all of before's pairs
//! (found with max_pairs 0).
std::vector<char> unchanged_clean_charts(const Charts& now, const Charts& before,
                                         const std::vector<std::pair<int, int>>& before_overlaps);

//! Seams that part faces f and g of one part of a layout (two sheets that overlap), `part` per
//! face (the chart, or a piece of one parted before): the part's faces, in groups that no seam
//! may split (`group` per face, e.g. the input face a piece lies in; empty: each face alone), are
//! shared out between the two by nearest group (Dijkstra across uncut edges, a step the distance
//! of the groups' centroids in `centroid`), the edges between the shares marked in `cut`, and g's
//! share labelled `new_part` in `part`. Returns the number of edges marked (0: nothing changed,
//! also where f and g are in different parts). A piece of a developed chart keeps its layout up to
//! a rigid motion and rounding (see overlap_depth), so the pairs of a chart that overlap deeply
//! can be parted one after the other, before laying out again. Where a part is not connected (a
//! group split by an earlier seam inside it), its label covers its components together.
//! \pre new_part is a label no face has.
int separate_sheets(const Triangulation& mesh, std::vector<int>& part, int new_part, int f, int g,
                    const std::vector<int>& group, const std::vector<Eigen::Vector3d>& centroid,
                    std::vector<char>& cut);

//! How far from the middle of two overlapping faces f and g a SheetSeparator given lengths may
//! part them: levels of d_f - d_g within this share of d_f(g), each side from a quarter to three
//! quarters of the way. Measured on 453 atlases (the real-mesh set, CGAL's meshes, game assets,
//! furniture), seams median over sqrt(area): 4.62 with the nearest groups' seam; with any shorter
//! level taken, 4.37 with a band of 0.5 and 4.28 with one of 0.7 (with 0.7 charts more on 94
//! files and fewer on 67, utilization median 0.573 against 0.581 with 0.5); with a level taken
//! where a fifth shorter, as now, 4.41 with 0.5.
inline constexpr double kSeparationBand = 0.5;

//! separate_sheets for many pairs of one layout: the faces of each part are indexed once, so that
//! each pair costs its part's faces, not the mesh's. `part` is changed through this object only
//! while it is in use.
class SheetSeparator {
 public:
  SheetSeparator(const Triangulation& mesh, std::vector<int>& part);
  //! Given the edges' lengths (per edge of `mesh`, kept by reference), each pair may be parted
  //! at another level of d_f - d_g than 0, the two groups' distances as separate_sheets takes
  //! them, within kSeparationBand times d_f(g) of 0: the level whose edges between groups on its
  //! two sides are shortest in sum (of equal sums, the one nearest 0); f's share the groups below
  //! it connected to f, with what they enclose, g's the rest. That seam is taken where it is
  //! clearly shorter than the nearest groups' (by a fifth): a chart's sheets part at a neck near
  //! the middle, not across its width.
  SheetSeparator(const Triangulation& mesh, std::vector<int>& part,
                 const std::vector<double>& lengths);
  SheetSeparator(const Triangulation& mesh, std::vector<int>& part,
                 std::vector<double>&& lengths) = delete;
  //! separate_sheets(mesh, part, new_part, f, g, group, centroid, cut), or, given lengths, its
  //! seam moved to a neck as above (and a group at equal distances from f and g on f's side,
  //! where separate_sheets gives it to the one that reaches it first).
  int separate(int new_part, int f, int g, const std::vector<int>& group,
               const std::vector<Eigen::Vector3d>& centroid, std::vector<char>& cut);

 private:
  const Triangulation& mesh_;
  std::vector<int>& part_;
  std::vector<std::vector<int>> faces_;  // per part label, in increasing order
  std::vector<int> local_;               // per group, its number in the part at hand (else -1)
  // The shares of the part's groups (`share`, by local group; the part's groups in `member`
  // from `first`): each to the nearer of the two seeds' groups, by one search from both.
  void nearest_share(int chart, const std::vector<int>& member, const std::vector<int>& first,
                     const std::vector<int>& group, const std::vector<Eigen::Vector3d>& centroid,
                     const int seeds[2], const std::vector<char>& cut,
                     std::vector<int>& share) const;
  // The same from a search from each seed (at equal distances to f's); then, where a level of
  // the two distances' difference within the band parts f's share from g's along a clearly
  // shorter seam than the nearest groups', that one instead.
  void shares_by_distances(int chart, const std::vector<int>& member, const std::vector<int>& first,
                           const std::vector<int>& group,
                           const std::vector<Eigen::Vector3d>& centroid, const int seeds[2],
                           const std::vector<char>& cut, std::vector<int>& share) const;
  const std::vector<double>* lengths_ = nullptr;
};

}  // namespace ricci
