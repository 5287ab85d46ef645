// Time of a whole E2 Yamabe flow (free boundary, to max |K - Kbar| <= 1e-10) on a real disk scan
// at about 17k, 67k, 267k and 1.07M faces, with and without edge flips, next to one CHOLMOD
// numeric factorization of the same Hessian. Run by bench/run.sh in a Release build.
#include <benchmark/benchmark.h>

#include "bench_meshes.h"
#include "flow/hessian.h"
#include "flow/metric.h"
#include "ricci/flow/ricci_flow.h"
#include "ricci/linear/linear_solver.h"

namespace ricci::bench {
namespace {

SchemeOptions yamabe() {
  SchemeOptions o;
  o.scheme = Scheme::Yamabe;
  return o;
}

// range(0): subdivision level; range(1): 1 with edge flips (the default), 0 without.
void BM_YamabeFlowToConvergence(benchmark::State& state) {
  const CompactMesh& mesh = lion_head(static_cast<int>(state.range(0)));
  const TargetCurvature target = TargetCurvature::free_boundary(mesh);
  FlowOptions options;
  options.edge_flips = state.range(1) != 0 ? EdgeFlips::Always : EdgeFlips::Never;
  FlowResult last;
  for (auto _ : state) {
    last = compute_ricci_flow(mesh, Geometry::Euclidean, yamabe(), target, options);
    benchmark::DoNotOptimize(last.u.data());
  }
  state.counters["faces"] = mesh.num_faces();
  state.counters["newton_iterations"] = last.iterations;
  state.counters["residual"] = last.residual;
  state.counters["s_per_iteration"] = last.times.total / std::max(1, last.iterations);
  state.counters["s_factorization_total"] = last.times.factorization;
  state.counters["s_analysis"] = last.times.analysis;
  state.counters["s_assembly_total"] = last.times.assembly;
  state.counters["s_line_search_total"] = last.times.line_search;
  state.counters["edge_flips"] = last.num_flips;
  state.counters["s_flips_total"] = last.times.flips;
  state.counters["symbolic_analyses"] = last.num_analyses;
}

void BM_CholmodNumericFactorization(benchmark::State& state) {
  const CompactMesh& mesh = lion_head(static_cast<int>(state.range(0)));
  const TargetCurvature target = TargetCurvature::free_boundary(mesh);
  const ConformalStructure s = prepare_flow(mesh, Geometry::Euclidean, yamabe(), target);
  std::vector<int> free_index(mesh.num_vertices(), -1);
  int n = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!target.is_fixed(v)) free_index[v] = n++;
  }
  HessianAssembler assembler(mesh, free_index);
  const SparseMatrix& h = assembler.assemble(evaluate_metric(mesh, s, s.u0));
  LinearSolver solver(LinearSolverKind::Cholmod);
  solver.analyze(h);
  for (auto _ : state) {
    benchmark::DoNotOptimize(solver.factorize(h));
  }
  state.counters["faces"] = mesh.num_faces();
  state.counters["unknowns"] = n;
}

BENCHMARK(BM_YamabeFlowToConvergence)
    ->ArgsProduct({{0, 1, 2, 3}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_CholmodNumericFactorization)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

}  // namespace
}  // namespace ricci::bench

BENCHMARK_MAIN();
