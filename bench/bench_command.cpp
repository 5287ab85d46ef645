// The whole ricci-flow command, reading and writing included, as a user runs it: CGAL's
// lion-head.off subdivided to 267k and 1.07M faces (written to an OFF file before timing) with a
// free boundary and onto the unit disk, and bunny00.off onto the sphere. Each run's own report
// gives the time of its numeric factorizations, so the counter `in_factorizations` (whole run
// over one factorization of the same mesh's Hessian, in the same run) travels between machines.
// Run by bench/run.sh in a Release build.
#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app.h"
#include "bench_meshes.h"
#include "flow/hessian.h"
#include "flow/metric.h"
#include "ricci/flow/ricci_flow.h"
#include "ricci/linear/linear_solver.h"
#include "test_meshes.h"

namespace ricci::bench {
namespace {

std::string temporary(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("ricci-bench-" + name)).string();
}

// lion-head.off subdivided `levels` times, as an OFF file (written once).
std::string lion_head_file(int levels) {
  const std::string path = temporary("lion-head-" + std::to_string(levels) + ".off");
  if (std::filesystem::exists(path)) return path;
  const CompactMesh& mesh = lion_head(levels);
  std::ofstream out(path);
  out.precision(17);
  out << "OFF\n" << mesh.num_vertices() << " " << mesh.num_faces() << " 0\n";
  for (const auto& p : mesh.positions()) out << p.x() << " " << p.y() << " " << p.z() << "\n";
  for (const auto& f : mesh.faces()) out << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
  return path;
}

// A number of the JSON report: the value after the first "key": (numeric_factorizations,
// flows and read come first as the whole run's totals).
double report_number(const std::string& json, const std::string& key) {
  const size_t at = json.find("\"" + key + "\":");
  if (at == std::string::npos) return 0;
  return std::stod(json.substr(at + key.size() + 3));
}

void run_command(benchmark::State& state, const std::string& input,
                 const std::vector<std::string>& options) {
  const std::string output = temporary("out.ply"), report = temporary("report.json");
  std::vector<std::string> args = {"ricci-flow", input,  "-o",     output,
                                   "--report",   report, "--quiet"};
  args.insert(args.end(), options.begin(), options.end());
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  int code = 0;
  double elapsed = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    code = cli::run_command_line(static_cast<int>(argv.size()), argv.data());
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  if (code != 0) {
    state.SkipWithError("ricci-flow failed");
    return;
  }
  std::ifstream in(report);
  std::stringstream json;
  json << in.rdbuf();
  const double factorizations = report_number(json.str(), "numeric_factorizations");
  const double seconds = report_number(json.str(), "factorization");
  const double one = seconds / factorizations;
  state.counters["in_factorizations"] = elapsed / one;
  state.counters["factorizations"] = factorizations;
  state.counters["one_factorization_s"] = one;
  state.counters["read_s"] = report_number(json.str(), "read");
  state.counters["flows"] = report_number(json.str(), "flows");  // their number
  state.counters["minres_iterations"] = report_number(json.str(), "krylov_iterations");
}

// range(0): subdivision level of lion-head.off (2: 267k faces, 3: 1.07M).
void BM_CommandFreeBoundary(benchmark::State& state) {
  run_command(state, lion_head_file(static_cast<int>(state.range(0))),
              {"--target", "free-boundary"});
}

void BM_CommandUnitDisk(benchmark::State& state) {
  run_command(state, lion_head_file(static_cast<int>(state.range(0))), {});
}

// Seconds of one numeric factorization (the fastest of three) of a Hessian with mesh's pattern:
// the Euclidean Yamabe one at the input (its target only has to satisfy Gauss-Bonnet), one vertex
// held (positive definite).
double factorization_of_hessian(const CompactMesh& mesh) {
  SchemeOptions yamabe;
  yamabe.scheme = Scheme::Yamabe;
  const double gauss_bonnet = 2 * kPi * mesh.euler_characteristic() / mesh.num_vertices();
  const TargetCurvature target = TargetCurvature::from_values(
      mesh, Eigen::VectorXd::Constant(mesh.num_vertices(), gauss_bonnet));
  const ConformalStructure s = prepare_flow(mesh, Geometry::Euclidean, yamabe, target);
  std::vector<int> free_index(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) free_index[v] = v - 1;
  HessianAssembler assembler(mesh, free_index);
  const SparseMatrix& h = assembler.assemble(evaluate_metric(mesh, s, s.u0));
  LinearSolver solver(LinearSolverKind::Cholmod);
  solver.analyze(h);
  double best = 1e300;
  for (int repeat = 0; repeat < 3; ++repeat) {
    const auto start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(solver.factorize(h));
    best = std::min(
        best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

// The sphere's steps factorize H^2 + mu I; the counter in_h_factorizations states the whole run
// in factorizations of H itself (the unit of the tracker's goal for this row).
void BM_CommandSphere(benchmark::State& state) {
  run_command(state, test::cgal_mesh_path("bunny00.off"), {});
  const double one_h = factorization_of_hessian(test::cgal_mesh("bunny00.off"));
  state.counters["one_h_factorization_s"] = one_h;
  state.counters["in_h_factorizations"] =
      state.counters["in_factorizations"] * state.counters["one_factorization_s"] / one_h;
}

BENCHMARK(BM_CommandFreeBoundary)
    ->DenseRange(2, 3)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_CommandUnitDisk)
    ->DenseRange(2, 3)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_CommandSphere)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

}  // namespace
}  // namespace ricci::bench

BENCHMARK_MAIN();
