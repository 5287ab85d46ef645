// The PLY file ricci-flow writes: a contract that scripts, tests and MeshLab read.
//
// vertex: x y z (the input's vertices in their order, then the copies a repair made), ricci_u
// ricci_radius ricci_curvature ricci_target (double; NaN for a vertex in no face; ricci_target is
// NaN where u was held fixed), and where a single-valued layout exists layout_x layout_y layout_z
// (double; NaN for vertices of components without one) plus, when every component is laid out in
// the plane one position per vertex, texture_u texture_v (float). face: vertex_indices (the
// repaired faces, component after component), and when a component is cut open (torus in E2, H2
// in the Poincare disk), or planar charts share the file with a sphere, texcoord for every face,
// 6 floats (u v per corner, in [0, 1]; 0 for the sphere's faces), which MeshLab reads as wedge
// texture coordinates, texcoord_double, the same in double precision (thin faces can turn over
// when rounded to float), ricci_chart (int: the Poincare disk chart or atlas chart the face is
// drawn in, a component in one piece one chart, -1 for a face without one; numbered across the
// components, each one's on from those before it) and layout_corners (6 doubles: x y per corner in
// the layout's model before any normalization: the plane in the metric's units, the Poincare
// disk in the face's chart, every vertex at its point of the conformal map, so that the faces are
// hyperbolic triangles whose copies across the cut are images under the deck transformations,
// where the texture may draw a few new vertices on their faces' straight sides instead; NaN for
// faces on the sphere or without a layout). Whenever a component
// has a layout, the face property ricci_layout (uchar) says whose: 0 none, 1 the plane, 2 the
// Poincare disk, 3 the unit sphere. When the flow flipped edges and the input's faces would turn
// over, the mesh is the common subdivision (common_subdivision.h; for an atlas, possibly the
// input's faces with some cut into their pieces: texture_atlas.h): the vertices above, then the new
// ones (on input edges, or inside input faces: common_subdivision.h), with vertex properties
// ricci_input_face (int, -1 for the repaired mesh's vertices) and ricci_bary_0..2 (double, the
// barycentric coordinates in that input face), and the face property ricci_input_face (int, the
// input face the face lies in).
#pragma once

#include <string>

#include "ricci/pipeline/atlas.h"

namespace ricci::cli {

//! \throws IoError when the file cannot be written.
void write_result_ply(const std::string& path, const MeshUniformization& run, bool ascii);

}  // namespace ricci::cli
