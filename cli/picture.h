// A PNG picture of a planar layout: faces coloured by the conformal factor, edges on top.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ricci::cli {

//! Renders texture coordinates in [0,1]^2 to a size x size PNG. Faces are coloured by the mean
//! of the per-vertex value: white at 0, blue below, red above, saturated at the largest |value|;
//! edges are drawn when there are few enough.
//! \throws IoError when the file cannot be written.
void write_layout_png(const std::string& path, const std::vector<std::array<int, 3>>& faces,
                      const std::vector<Eigen::Vector2d>& uv, const Eigen::VectorXd& value,
                      int size = 800);

}  // namespace ricci::cli
