// The ricci-flow command: parse, read and repair, uniformize, write; exit codes 0, 1 (the run
// failed), 2 (usage).
#include "app.h"

#include <malloc.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "options.h"
#include "picture.h"
#include "result_obj.h"
#include "result_ply.h"
#include "ricci/io/mesh_io.h"
#include "ricci/linear/vertex_order.h"
#include "ricci/mesh/errors.h"
#include "ricci/pipeline/atlas.h"
#include "ricci/pipeline/uniformize.h"
#include "ricci/repair/repair.h"
#include "ricci/report/report.h"

namespace {

using namespace ricci;

// An output named *.obj (any case) is written as OBJ, any other as PLY.
bool is_obj_name(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".obj";
}

// --target cones:FILE or FILE, or --cones FILE: the per-vertex target, read once the mesh is
// known.
void read_target_file(const cli::Options& o, UniformizationOptions& r) {
  const std::string& cones =
      o.cones_file.empty() && o.target_is_cones ? o.target_file : o.cones_file;
  if (!cones.empty()) {
    for (const auto& [vertex, degrees] : cli::read_cones(cones)) {
      r.cones.push_back({vertex, degrees * kPi / 180});
    }
    if (r.cones.empty()) throw IoError(cones + ": no cones in it (lines \"VERTEX ANGLE_DEGREES\")");
    return;
  }
  if (o.target_file.empty()) return;
  const std::vector<double> values = cli::read_numbers(o.target_file);
  r.values = Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<long>(values.size()));
}

std::vector<int> read_eps(const std::string& path, int num_vertices) {
  const std::vector<double> values = cli::read_numbers(path);
  if (static_cast<int>(values.size()) != num_vertices) {
    throw InvalidArgumentError("--eps " + path + ": " + std::to_string(values.size()) +
                               " values for " + std::to_string(num_vertices) +
                               " vertices; give one of +1, 0, -1 per vertex");
  }
  std::vector<int> eps(values.size());
  for (size_t v = 0; v < values.size(); ++v) {
    if (values[v] != 1 && values[v] != 0 && values[v] != -1) {
      throw InvalidArgumentError("--eps " + path + ": vertex " + std::to_string(v) + " has " +
                                 std::to_string(values[v]) + "; each value must be +1, 0 or -1");
    }
    eps[v] = static_cast<int>(values[v]);
  }
  return eps;
}

// Every delivered face's corners index the per-vertex texture coordinates (disks and circle
// domains; components cut open have per-corner ones only).
bool one_position_per_vertex(const MeshUniformization& run) {
  for (const auto& face : run.faces) {
    for (int v : face) {
      if (v < 0 || v >= static_cast<int>(run.texture.vertex.size())) return false;
    }
  }
  return true;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  if (!out) throw IoError("cannot write '" + path + "'");
  out << text;
  out.close();
  if (!out) throw IoError("writing '" + path + "' failed");
}

// A run's output files, each written beside its target under a temporary name and renamed into
// place by commit() once all are written: a run that fails part way (a full disk, a picture that
// cannot be written) leaves none of them, and no truncated file under the target's name. A target
// that exists and is no regular file (/dev/null, a symlink, a pipe) is written to directly.
class PendingOutputs {
 public:
  PendingOutputs() = default;
  PendingOutputs(const PendingOutputs&) = delete;
  PendingOutputs& operator=(const PendingOutputs&) = delete;
  ~PendingOutputs() {
    for (const auto& file : files_) std::remove(file.second.c_str());
  }

  //! Calls write_to with the name to write `path` under until commit(); its errors name `path`.
  //! \throws IoError for a target that is a directory, or named for two outputs.
  template <class Write>
  void write(const std::string& path, const Write& write_to) {
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::symlink_status(path, error);
    if (std::filesystem::is_directory(status)) {
      throw IoError("cannot write '" + path + "': it is a directory");
    }
    for (const std::string& earlier : targets_) {
      if (earlier == path) throw IoError("cannot write '" + path + "' twice (two outputs name it)");
    }
    targets_.push_back(path);
    if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
      write_to(path);
      return;
    }
    static std::atomic<int> count{0};
    files_.emplace_back(path, path + ".ricci-flow-" + std::to_string(getpid()) + "-" +
                                  std::to_string(count++) + ".part");
    const std::string& temporary = files_.back().second;
    try {
      write_to(temporary);
    } catch (const IoError& e) {
      std::string what = e.what();
      for (size_t at = what.find(temporary); at != std::string::npos; at = what.find(temporary))
        what.replace(at, temporary.size(), path);
      throw IoError(what);
    }
  }

  void commit() {
    for (const auto& [path, temporary] : files_) {
      if (std::rename(temporary.c_str(), path.c_str()) != 0) {
        throw IoError("cannot write '" + path + "' (renaming '" + temporary +
                      "' failed: " + std::strerror(errno) + ")");
      }
    }
    files_.clear();
  }

 private:
  std::vector<std::string> targets_;
  std::vector<std::pair<std::string, std::string>> files_;  // target, temporary
};

}  // namespace

namespace ricci::cli {

UniformizationOptions request_for(const Options& o, int num_input_vertices) {
  UniformizationOptions request = o.request;
  read_target_file(o, request);
  if (!o.eps_file.empty()) request.scheme.eps = read_eps(o.eps_file, num_input_vertices);
  return request;
}

// The input, read and repaired (the file's own arrays freed); for a large mesh, the flow's
// fill-reducing ordering starts on the other core as soon as the faces are read, to run while the
// mesh is repaired and the flow set up.
RepairedMesh read_and_repair(const Options& o, VertexOrder& order) {
  const MeshFile file = read_mesh_file(o.input);
  // The ordering's thread allocates from a malloc arena of its own, which glibc keeps after the
  // thread is done: returned (before the flow's large blocks exist), the 1.07M-face runs peaked
  // at 1.23 GB instead of 1.32 GB. (One arena for all threads instead peaked at 1.25 GB, and its
  // flows took 5.0 to 6.0 s against 4.7 to 5.3 s in three alternating runs.)
  order = VertexOrder::start(static_cast<int>(file.positions.size()), file.triangles,
                             kNestedDissectionRows, [] { malloc_trim(0); });
  // Faces of fewer than three corners (OBJ's "f 1 2", OFF's "2 0 1") are no surface: dropped,
  // and said so, as the repairs are (--strict: refused).
  if (file.skipped_faces > 0 && o.repair.strict) {
    throw InvalidMeshError(o.input + ": " + std::to_string(file.skipped_faces) +
                           " faces with fewer than three corners (--strict)");
  }
  try {
    RepairedMesh repaired = repair_mesh(file.positions, file.triangles, o.repair);
    if (file.skipped_faces > 0) {
      repaired.report.entries.insert(
          repaired.report.entries.begin(),
          {"faces with fewer than three corners dropped", "face", file.skipped_faces, {}});
    }
    return repaired;
  } catch (const InvalidMeshError& e) {
    throw InvalidMeshError(o.input + ": " + e.what());
  }
}

// Each line search trial and Newton step allocates arrays of up to 160 MB on a million faces.
// glibc maps blocks above 32 MB afresh and unmaps them when freed, so each costs page faults and
// zeroing by the kernel again; kept in the heap (a process-wide setting: this is the command's,
// not the library's), they are reused: at 1.07M faces the line search took 0.65 s instead of
// 1.1 s. Below kHeapKeptFromFaces faces glibc's own thresholds keep such blocks in the heap
// anyway, and return freed memory: raised there, the heap never shrinks, and bunny00.off's sphere
// peaked at 164 MB instead of 146 MB.
constexpr int kHeapKeptFromFaces = 200000;
void keep_large_blocks_in_heap(const RepairedMesh& mesh) {
  long faces = 0;
  for (const MeshComponent& c : mesh.components) faces += c.mesh.num_faces();
  if (faces < kHeapKeptFromFaces) return;
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

void run(const Options& o) {
  const bool show_progress = !o.quiet && isatty(fileno(stderr));
  const auto read_start = std::chrono::steady_clock::now();
  VertexOrder order;
  RepairedMesh repaired = read_and_repair(o, order);
  keep_large_blocks_in_heap(repaired);
  RunContext context{o.input, o.target, 0};
  context.read_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();

  UniformizationOptions request = request_for(o, repaired.num_input_vertices);
  request.vertex_order = order;
  if (show_progress) {
    request.flow.progress = [](const FlowProgress& p) {
      std::fprintf(stderr, "\riteration %3d   max |K - Kbar| = %.3e ", p.iteration, p.residual);
      return true;
    };
  }
  if (!o.picture.empty()) {
    for (const LayoutKind kind : planned_layouts(repaired, request)) {
      if (kind == LayoutKind::Plane) continue;
      throw InvalidArgumentError(
          "--picture needs a layout in the plane (a disk, or a circle domain with --target "
          "disk); this run is laid out as " +
          to_string(kind));
    }
  }
  const MeshUniformization run = uniformize_mesh(std::move(repaired), request);
  if (show_progress) std::fprintf(stderr, "\n");
  if (!o.report.empty()) {
    // The report is delivered for a failed run too: it says why.
    PendingOutputs report;
    report.write(o.report,
                 [&](const std::string& to) { write_text(to, json_report(run, context)); });
    report.commit();
  }
  run.require_valid(o.input);
  if (!o.picture.empty() && !one_position_per_vertex(run)) {
    // The automatic target can give a circle domain's component the free boundary, cut open.
    throw InvalidArgumentError(
        "--picture needs a layout in the plane with one position per vertex; a component was "
        "cut open (the free boundary instead of its circle domain, see the summary)");
  }
  PendingOutputs outputs;
  outputs.write(o.output, [&](const std::string& to) {
    if (is_obj_name(o.output)) {
      write_result_obj(to, run);
    } else {
      write_result_ply(to, run, o.ascii);
    }
  });
  if (!o.picture.empty()) {
    outputs.write(o.picture, [&](const std::string& to) {
      write_layout_png(to, run.faces, run.texture.vertex, run.u);
    });
  }
  outputs.commit();
  if (!o.quiet) {
    for (const std::string& line : summary_lines(run, context)) std::printf("%s\n", line.c_str());
    for (const std::string& path : {o.output, o.picture, o.report}) {
      if (!path.empty()) std::printf("wrote %s\n", path.c_str());
    }
  }
}

int run_command_line(int argc, const char* const* argv) {
  Options options;
  try {
    options = parse_options(argc, argv);
  } catch (const Error& e) {
    std::fprintf(stderr, "ricci-flow: error: %s\n", e.what());
    return 2;
  }
  if (options.help) {
    std::fputs(usage().c_str(), stdout);
    return 0;
  }
  if (options.version) {
    std::puts("ricci-flow 0.1.0");
    return 0;
  }
  try {
    run(options);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ricci-flow: error: %s\n", failure_message(e).c_str());
    return 1;
  }
}

void end_process(int code) {
  std::fflush(nullptr);
  std::_Exit(code);
}

}  // namespace ricci::cli
