// Time of the atlas target (--target atlas) on real closed meshes of genus 0, 4 and 22, the whole
// pipeline (repair, cone placement, flow, subdivision, seams, charts, packing), and the unit that
// travels between machines: one numeric factorization of the same mesh's Yamabe Hessian at u = 0
// (one vertex pinned). Run by bench/run.sh in a Release build.
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "flow/hessian.h"
#include "flow/metric.h"
#include "ricci/flow/cone_placement.h"
#include "ricci/flow/ricci_flow.h"
#include "ricci/io/mesh_io.h"
#include "ricci/layout/packing.h"
#include "ricci/pipeline/atlas.h"

namespace ricci::bench {
namespace {

const std::vector<std::string> kMeshes = {"pymeshlab-cow.obj", "openfoam-flange.stl",
                                          "glmark2-bunny.obj", "occt-tr12j.stl"};

const RepairedMesh& repaired(int k) {
  static std::vector<RepairedMesh> meshes(kMeshes.size());
  static std::vector<bool> read(kMeshes.size(), false);
  if (!read[k]) {
    const MeshFile file = read_mesh_file(std::string(RICCI_REAL_MESH_DIR) + "/" + kMeshes[k]);
    meshes[k] = repair_mesh(file.positions, file.triangles);
    read[k] = true;
  }
  return meshes[k];
}

// The mesh's Yamabe Hessian at u = 0 with u held at vertex 0 (its row pinned): a target every
// topology admits in E2.
SparseMatrix pinned_hessian(const CompactMesh& mesh) {
  Eigen::VectorXd values = Eigen::VectorXd::Zero(mesh.num_vertices());
  values[0] = std::nan("");
  const TargetCurvature target = TargetCurvature::from_values(mesh, values);
  const ConformalStructure s = prepare_flow(mesh, Geometry::Euclidean, SchemeOptions(), target);
  std::vector<int> free_index(mesh.num_vertices(), -1);
  for (int v = 1; v < mesh.num_vertices(); ++v) free_index[v] = v - 1;
  HessianAssembler assembler(mesh, free_index);
  return assembler.assemble(evaluate_metric(mesh, s, s.u0));
}

// range(0): the mesh.
void BM_Atlas(benchmark::State& state) {
  const RepairedMesh& mesh = repaired(static_cast<int>(state.range(0)));
  UniformizationOptions options;
  options.preset = TargetPreset::Atlas;
  MeshUniformization last;
  for (auto _ : state) {
    last = uniformize_mesh(mesh, options);
    benchmark::DoNotOptimize(last.texture.wedge.data());
  }
  if (!last.valid()) state.SkipWithError("no valid atlas");
  const Uniformization& run = last.components.front();
  state.SetLabel(kMeshes[state.range(0)]);
  state.counters["faces"] = mesh.components.front().mesh.num_faces();
  state.counters["cones"] = static_cast<double>(run.atlas.placement.cones.size());
  state.counters["placement_back_solves"] = run.atlas.placement.back_solves;
  state.counters["s_placement"] = run.atlas.placement.seconds;
  state.counters["flow_factorizations"] = run.totals.numeric_factorizations;
  state.counters["charts"] = run.atlas.num_charts;
  state.counters["distortion"] = run.atlas.flow_distortion;
  // Of the texture: a component of several is packed only with the others.
  state.counters["utilization"] =
      last.components.size() == 1 ? run.atlas.utilization : last.packed.utilization;
}

void BM_AtlasMeshHessianFactorization(benchmark::State& state) {
  const CompactMesh& mesh = repaired(static_cast<int>(state.range(0))).components.front().mesh;
  const SparseMatrix h = pinned_hessian(mesh);
  LinearSolver solver(LinearSolverKind::Cholmod);
  solver.analyze(h);
  for (auto _ : state) {
    // The input's Hessian may be indefinite (obtuse faces); a small shift keeps it factorable.
    benchmark::DoNotOptimize(solver.factorize(h, 1e-8));
  }
  state.SetLabel(kMeshes[state.range(0)]);
  state.counters["unknowns"] = mesh.num_vertices() - 1;
}

// The cone stage alone (place_cones: the linear model built and factored, the greedy, the
// sweeps, the drops), range(1) the cone budget (0: the default bound D <= 0.2). Its time over
// BM_AtlasMeshHessianFactorization's is the stage's cost in factorizations.
void BM_AtlasConePlacement(benchmark::State& state) {
  const CompactMesh& mesh = repaired(static_cast<int>(state.range(0))).components.front().mesh;
  ConePlacementOptions options;
  options.max_cones = static_cast<int>(state.range(1));
  ConePlacement last;
  for (auto _ : state) {
    last = place_cones(mesh, options);
    benchmark::DoNotOptimize(last.u.data());
  }
  state.SetLabel(kMeshes[state.range(0)]);
  state.counters["cones"] = static_cast<double>(last.cones.size());
  state.counters["columns"] = last.back_solves;
  state.counters["distortion"] = last.distortion;
}

// The packing alone: the charts of the mesh's atlas (its default bound), as laid out before
// packing, packed into the unit square (pack_charts, with the default texture and padding).
void BM_AtlasPacking(benchmark::State& state) {
  const RepairedMesh& mesh = repaired(static_cast<int>(state.range(0)));
  UniformizationOptions options;
  options.preset = TargetPreset::Atlas;
  const MeshUniformization atlas = uniformize_mesh(mesh, options);
  // Charts are numbered per component, in its own units: one component's (each bench mesh's).
  if (atlas.components.size() != 1) {
    state.SkipWithError("a mesh of one component only");
    return;
  }
  std::vector<std::vector<std::array<Eigen::Vector2d, 3>>> charts;
  for (size_t f = 0; f < atlas.corners.size(); ++f) {
    const int k = atlas.face_chart[f];
    if (k < 0) continue;
    if (k >= static_cast<int>(charts.size())) charts.resize(k + 1);
    const auto& c = atlas.corners[f];
    charts[k].push_back({c[0].head<2>(), c[1].head<2>(), c[2].head<2>()});
  }
  Packing last;
  for (auto _ : state) {
    last = pack_charts(charts);
    benchmark::DoNotOptimize(last.offset.data());
  }
  state.SetLabel(kMeshes[state.range(0)]);
  state.counters["charts"] = static_cast<double>(charts.size());
  state.counters["utilization"] = last.utilization;
}

// The cone placement's unit of work: columns R(e_v) of the factored Hessian, solved range(1) at a
// time (one right-hand side per column) by CHOLMOD (range(2) 0) or as sparse right-hand sides
// (range(2) 1: solve_sparse, as the placement solves them); per column, in the counter, against
// one factorization.
void BM_AtlasConeColumns(benchmark::State& state) {
  const CompactMesh& mesh = repaired(static_cast<int>(state.range(0))).components.front().mesh;
  const SparseMatrix h = pinned_hessian(mesh);
  LinearSolver solver(LinearSolverKind::Cholmod);
  solver.analyze(h);
  solver.factorize(h, 1e-8);
  const long block = state.range(1);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(h.rows(), block);
  for (long j = 0; j < block; ++j) b((j * 7919) % h.rows(), j) = 1;
  const SparseMatrix units = b.sparseView();
  const bool sparse = state.range(2) == 1;
  for (auto _ : state) {
    benchmark::DoNotOptimize((sparse ? solver.solve_sparse(units) : solver.solve(b)).data());
  }
  state.SetLabel(kMeshes[state.range(0)]);
  state.counters["columns"] = static_cast<double>(block);
  state.counters["per_column"] =
      benchmark::Counter(static_cast<double>(block), benchmark::Counter::kIsIterationInvariantRate |
                                                         benchmark::Counter::kInvert);
}

BENCHMARK(BM_Atlas)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_AtlasConePlacement)
    ->ArgsProduct({{0, 1, 2, 3}, {0, 8}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_AtlasConeColumns)
    ->ArgsProduct({{0, 2, 3}, {1, 8, 32}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_AtlasPacking)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_AtlasMeshHessianFactorization)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

}  // namespace
}  // namespace ricci::bench

BENCHMARK_MAIN();
