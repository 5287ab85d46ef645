// The OBJ file ricci-flow writes when the output's name ends in .obj: what texture tools read.
//
// v x y z per delivered vertex (the PLY's vertices, in the same order); vt u v, per vertex when
// the layout has one position per vertex, else one per distinct (vertex, texture position) pair
// of the faces' corners (a vertex on a seam has one per chart side); f a/t b/t c/t per delivered
// face (1-based), or f a b c without texture coordinates (the sphere). 17 significant digits.
#pragma once

#include <string>

#include "ricci/pipeline/atlas.h"

namespace ricci::cli {

//! \throws IoError when the file cannot be written.
void write_result_obj(const std::string& path, const MeshUniformization& run);

}  // namespace ricci::cli
