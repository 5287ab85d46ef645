// Command line of ricci-flow: parsing and the per-vertex input files.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ricci::cli {

struct Options {
  std::string input;
  std::string output;
  std::string geometry = "auto";  // auto, euclidean, hyperbolic, spherical
  std::string scheme = "yamabe";
  double angle_degrees = 60;    // Thurston's intersection angle
  std::string eps_file;         // mixed scheme: +1/0/-1 per vertex
  std::string target = "auto";  // auto, disk, zero, free-boundary, cones:FILE, or a file
  int center_vertex = -1;       // disk target: vertex mapped to the centre
  int axis_vertex = -1;         // disk target: vertex mapped onto the positive real axis
  double tolerance = 1e-10;
  int max_iterations = 100;
  std::string solver = "cholmod";
  bool edge_flips = true;
  std::string report;   // JSON report path
  std::string picture;  // PNG of the layout
  bool ascii = false;
  bool quiet = false;
  bool help = false;
  bool version = false;
};

//! Parses argv. \throws InvalidArgumentError with the usage problem.
Options parse_options(int argc, const char* const* argv);

std::string usage();

//! One number per line; blank lines and lines starting with # are skipped; "nan" allowed.
//! \throws IoError naming the file and line of a bad value.
std::vector<double> read_numbers(const std::string& path);

//! Lines "VERTEX ANGLE_DEGREES"; blank lines and lines starting with # are skipped.
//! \throws IoError naming the file and line of a bad line.
std::vector<std::pair<int, double>> read_cones(const std::string& path);

}  // namespace ricci::cli
