// Time of the disk target (uniformize.h): a real disk scan mapped onto the unit disk, at about 17k,
// 67k and 267k faces, Yamabe with the default edge flips: one solve with the circle condition in
// the Jacobian, and the layout. Run by bench/run.sh in a Release build.
#include <benchmark/benchmark.h>

#include "bench_meshes.h"
#include "ricci/pipeline/uniformize.h"

namespace ricci::bench {
namespace {

// range(0): subdivision level of lion-head.off.
void BM_UnitDiskMap(benchmark::State& state) {
  const CompactMesh& mesh = lion_head(static_cast<int>(state.range(0)));
  UniformizationOptions options;
  options.preset = TargetPreset::UnitDisk;
  Uniformization last;
  for (auto _ : state) {
    last = uniformize(mesh, options);
    benchmark::DoNotOptimize(last.position.data());
  }
  if (!last.result.converged) state.SkipWithError(last.result.failure.c_str());
  state.counters["faces"] = mesh.num_faces();
  state.counters["flows"] = last.totals.flows;
  state.counters["newton_iterations"] = last.totals.newton_iterations;
  state.counters["factorizations"] = last.totals.numeric_factorizations;
  state.counters["minres_iterations"] = last.totals.krylov_iterations;
  state.counters["circle_error"] = last.circle_error;
  state.counters["flipped_faces"] = last.quality.flipped_faces;
  state.counters["quasi_conformal_median"] = last.quality.quasi_conformal_median;
}

BENCHMARK(BM_UnitDiskMap)
    ->DenseRange(0, 2)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

}  // namespace
}  // namespace ricci::bench

BENCHMARK_MAIN();
