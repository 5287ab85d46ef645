// What one run reports, written once for every front end: the summary lines (ricci-flow's output
// and MeshLab's log), the JSON report (ricci-flow --report) and the numbers a script gets back
// (the dict pymeshlab returns).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "ricci/mesh/compact_mesh.h"
#include "ricci/pipeline/atlas.h"
#include "ricci/pipeline/uniformize.h"

namespace ricci {

//! What the pipeline does not know about a run.
struct RunContext {
  std::string input;        //!< the mesh's file, or its layer's name
  std::string target;       //!< the target as the user gave it
  double read_seconds = 0;  //!< reading the input
  //! A component of several, whose charts are packed only with the others' (not alone: its
  //! utilization and padding are NaN).
  bool packed_together = false;
};

//! The run in a few lines: mesh and settings, convergence, the unit disk's circles, the layout's
//! quality, the cut, the torus's periods.
std::vector<std::string> summary_lines(const CompactMesh& mesh, const Uniformization& run,
                                       const RunContext& context);

//! The JSON report: input, settings, convergence history of the last flow, counts and times
//! summed over every flow, errors, and the layout (quality, cut, deck transformations).
std::string json_report(const CompactMesh& mesh, const Uniformization& run,
                        const RunContext& context);

//! The headline numbers by name, in a fixed order: iterations, edge_flips, max_curvature_error,
//! flipped_faces, quasi_conformal_median, closure_error, circle_error, flows, collapsed_faces
//! (and, for a mesh of several components, components).
std::vector<std::pair<std::string, double>> result_numbers(const Uniformization& run);

//! The same for a whole mesh: its repairs, then each component's (the numbers: sums of counts,
//! the largest errors, and the number of components).
std::vector<std::string> summary_lines(const MeshUniformization& run, const RunContext& context);
std::string json_report(const MeshUniformization& run, const RunContext& context);
std::vector<std::pair<std::string, double>> result_numbers(const MeshUniformization& run);

//! max |l(u0) / (s l_input) - 1| over edges: how exactly the initial metric reproduces the input.
double initial_length_error(const CompactMesh& mesh, const ConformalStructure& structure);

//! sum K + kappa A - 2 pi chi of the result.
double gauss_bonnet_error(const CompactMesh& mesh, Geometry geometry, const FlowResult& result);

}  // namespace ricci
