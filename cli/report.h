// The JSON report of one ricci-flow run: input, settings, convergence history, timings, and
// the errors of the result.
#pragma once

#include <string>

#include "ricci/compact_mesh.h"
#include "ricci/ricci_flow.h"
#include "ricci/scheme.h"
#include "ricci/uniformize.h"

namespace ricci::cli {

struct RunSummary {
  std::string input;
  Scheme scheme = Scheme::Yamabe;
  std::string target;  //!< as given on the command line
  double tolerance = 0;
  double initial_length_error = 0;  //!< max relative error of the initial metric vs input
  double read_seconds = 0;
};

//! max |l(u0) / (s l_input) - 1| over edges: how exactly the initial metric reproduces the input.
double initial_length_error(const CompactMesh& mesh, const ConformalStructure& structure);

//! sum K + kappa A - 2 pi chi of the result.
double gauss_bonnet_error(const CompactMesh& mesh, Geometry geometry, const FlowResult& result);

//! \throws IoError
void write_report(const std::string& path, const CompactMesh& mesh, const RunSummary& run,
                  const Uniformization& u);

}  // namespace ricci::cli
