// Charts packed into the unit square at one texel density: each turned to its smallest bounding
// rectangle, rasterized (every cell within half the padding of it) and placed, largest first,
// where the atlas's extent grows least (bottom-left first among equals), in the best of its four
// quarter turns.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

namespace ricci {

struct PackingOptions {
  int texture_size = 1024;  //!< texels per side of the texture the atlas is for
  int padding = 4;          //!< texels between two charts
  //! Each chart in the four quarter turns of its drawing only, not first turned upright in its
  //! smallest box: charts turned to meet by quarter turns (turn_charts_to_quarter_turns) keep to
  //! them.
  bool quarter_turns_only = false;
};

//! Where chart k goes: uv = scale * rotation[k] * p + offset[k].
struct Packing {
  double scale = 1;
  std::vector<Eigen::Matrix2d> rotation;
  std::vector<Eigen::Vector2d> offset;
  double utilization = 0;  //!< the charts' area in the unit square
  //! Texels between two charts at least: the options' padding, or less where no packing gave it
  //! (more charts than the texture holds at that padding).
  double padding = 0;
  //! Charts packed into less than one texel's area of the texture (drawn in no texel of their
  //! own): a texture that size draws none of their faces.
  int below_a_texel = 0;
};

//! The smallest texture size packed for, in texels per side.
inline constexpr int kMinTextureSize = 16;

//! \throws InvalidArgumentError for a texture size below kMinTextureSize or a negative padding.
void check_packing_options(const PackingOptions& options);

//! Packs the charts (each a list of triangles, all in one length unit) into [0, 1]^2, keeping
//! their relative sizes. `expected_utilization` sizes the first packing's margin (the padding in
//! the charts' units): near what the packing gives (that of a packing of much the same charts),
//! no second packing is needed for the padding; outside (0, 1] it counts as 0.6, below 0.1 as 0.1.
//! \throws InvalidArgumentError for a texture size below kMinTextureSize or a negative padding.
Packing pack_charts(const std::vector<std::vector<std::array<Eigen::Vector2d, 3>>>& charts,
                    const PackingOptions& options = {}, double expected_utilization = 0.6);

}  // namespace ricci
