// Command line of ricci-flow: one table of flags drives parsing, --help and the defaults shown
// (taken from the core's option structs); every usage error is found before the mesh is read.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "ricci/pipeline/uniformize.h"
#include "ricci/repair/repair.h"

namespace ricci::cli {

struct Options {
  std::string input;
  std::string output;
  UniformizationOptions request;  //!< geometry, preset, scheme, flow, centre and axis
  std::string target = "auto";    //!< --target as given
  std::string target_file;        //!< --target cones:FILE or FILE: read once the mesh is known
  bool target_is_cones = false;
  std::string cones_file;  //!< --cones FILE: the atlas's cones, or alone the target cones:FILE
  std::string eps_file;    //!< mixed scheme: +1/0/-1 per vertex
  std::string atlas_flag;  //!< the first flag given that only --target atlas reads
  std::string report;      //!< JSON report path
  std::string picture;     //!< PNG of the layout
  RepairOptions repair;    //!< --strict, --keep-cuts
  bool ascii = false;
  bool quiet = false;
  bool help = false;
  bool version = false;
};

//! Parses argv. \throws InvalidArgumentError with the usage problem (the tool exits 2).
Options parse_options(int argc, const char* const* argv);

//! --help: generated from the flag table.
std::string usage();

//! One number per line; blank lines and lines starting with # are skipped; "nan" allowed.
//! \throws IoError naming the file and line of a bad value.
std::vector<double> read_numbers(const std::string& path);

//! Lines "VERTEX ANGLE_DEGREES"; blank lines and lines starting with # are skipped.
//! \throws IoError naming the file and line of a bad line.
std::vector<std::pair<int, double>> read_cones(const std::string& path);

}  // namespace ricci::cli
