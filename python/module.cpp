// ricci_flow._ricci_flow: the compiled part of the Python package. NumPy arrays in and out; the
// options are the command line tool's flags (parsed by its own table), so both take the same
// names, values and defaults. The Python layer (ricci_flow/__init__.py) turns keyword arguments
// into flags and the dicts returned here into result objects.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "app.h"
#include "options.h"
#include "ricci/flow/ricci_flow.h"
#include "ricci/io/mesh_io.h"
#include "ricci/mesh/errors.h"
#include "ricci/pipeline/atlas.h"
#include "ricci/repair/repair.h"
#include "ricci/report/report.h"

namespace nb = nanobind;

namespace {

using namespace ricci;

using Points = nb::ndarray<const double, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Triangles = nb::ndarray<const std::int64_t, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Values = nb::ndarray<const double, nb::shape<-1>, nb::c_contig, nb::device::cpu>;

// A NumPy array owning `data` (moved to the heap, freed with the array).
template <class T>
nb::object numpy(std::vector<T>&& data, std::initializer_list<size_t> shape) {
  auto* owned = new std::vector<T>(std::move(data));
  nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
  return nb::cast(nb::ndarray<nb::numpy, T>(owned->data(), shape, owner));
}

nb::object points(const std::vector<Eigen::Vector3d>& p) {
  std::vector<double> flat;
  flat.reserve(3 * p.size());
  for (const auto& x : p) flat.insert(flat.end(), {x.x(), x.y(), x.z()});
  return numpy(std::move(flat), {p.size(), 3});
}

nb::object triangles(const std::vector<std::array<int, 3>>& faces) {
  std::vector<std::int64_t> flat;
  flat.reserve(3 * faces.size());
  for (const auto& f : faces) flat.insert(flat.end(), {f[0], f[1], f[2]});
  return numpy(std::move(flat), {faces.size(), 3});
}

nb::object vector(const Eigen::VectorXd& v) {
  return numpy(std::vector<double>(v.data(), v.data() + v.size()), {static_cast<size_t>(v.size())});
}

nb::object indices(const std::vector<int>& v) {
  return numpy(std::vector<std::int64_t>(v.begin(), v.end()), {v.size()});
}

std::vector<Eigen::Vector3d> to_points(const Points& a) {
  std::vector<Eigen::Vector3d> p(a.shape(0));
  for (size_t i = 0; i < p.size(); ++i) p[i] = {a(i, 0), a(i, 1), a(i, 2)};
  return p;
}

std::vector<std::array<int, 3>> to_triangles(const Triangles& a) {
  std::vector<std::array<int, 3>> f(a.shape(0));
  for (size_t i = 0; i < f.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const std::int64_t v = a(i, static_cast<size_t>(c));
      if (v < 0 || v > std::numeric_limits<int>::max()) {
        throw InvalidMeshError("face " + std::to_string(i) + " has vertex index " +
                               std::to_string(v) + ", out of range");
      }
      f[i][c] = static_cast<int>(v);
    }
  }
  return f;
}

// argv of strings, for the command line tool's functions.
std::vector<const char*> argv_of(const std::vector<std::string>& args) {
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  return argv;
}

cli::Options parse(const std::string& caller, std::vector<std::string> flags) {
  flags.insert(flags.begin(), {caller, "<arrays>", "-o", "<arrays>.ply"});
  const std::vector<const char*> argv = argv_of(flags);
  return cli::parse_options(static_cast<int>(argv.size()), argv.data());
}

// Positions per delivered face corner, component after component; None unless every component
// has a layout.
nb::object corner_layout(const MeshUniformization& run) {
  for (LayoutKind kind : run.face_layout) {
    if (kind == LayoutKind::None) return nb::none();
  }
  std::vector<double> flat;
  flat.reserve(9 * run.faces.size());
  for (const auto& face : run.corners) {
    for (const auto& p : face) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  }
  return numpy(std::move(flat), {run.faces.size(), 3, 3});
}

nb::dict uniformize_arrays(const Points& v, const Triangles& f, std::vector<std::string> flags) {
  const cli::Options o = parse("ricci_flow.uniformize", std::move(flags));
  std::vector<Eigen::Vector3d> positions = to_points(v);
  std::vector<std::array<int, 3>> faces = to_triangles(f);
  MeshUniformization run;
  std::string report, failure;
  std::vector<std::string> summary;
  {
    nb::gil_scoped_release released;
    RepairedMesh repaired = repair_mesh(positions, faces, o.repair);
    const UniformizationOptions request = cli::request_for(o, repaired.num_input_vertices);
    run = uniformize_mesh(std::move(repaired), request);
    report = json_report(run, RunContext{"<arrays>", o.target, 0});
    try {
      run.require_valid();
    } catch (const Error& e) {
      failure = e.what();
    }
    // As the command line tool, the summary of a valid run only.
    if (failure.empty()) summary = summary_lines(run, RunContext{"<arrays>", o.target, 0});
  }
  nb::dict d;
  d["failure"] = failure;
  d["report"] = report;
  d["summary"] = summary;
  d["vertices"] = points(run.positions);
  d["faces"] = triangles(run.faces);
  d["input_face"] = indices(run.input_face);
  d["vertex_input_face"] = indices(run.vertex_input_face);
  d["vertex_barycentric"] = points(run.vertex_barycentric);
  d["u"] = vector(run.u);
  d["radius"] = vector(run.radius);
  d["curvature"] = vector(run.curvature);
  d["target"] = vector(run.target);
  d["position"] = run.position.empty() ? nb::none() : points(run.position);
  d["corner_layout"] = corner_layout(run);
  // Per delivered face its Poincare disk chart, where some component is drawn in several.
  bool charts = false;
  for (const Uniformization& c : run.components) charts = charts || !c.face_chart.empty();
  d["face_chart"] = charts ? indices(run.face_chart) : nb::none();
  // The atlas target's cones: delivered vertex and angle in the exact metric.
  std::vector<int> cone_vertices;
  std::vector<double> cone_angles;
  for (const Cone& c : run.cones) cone_vertices.push_back(c.vertex), cone_angles.push_back(c.angle);
  d["cones"] = indices(cone_vertices);
  d["cone_angles"] = numpy(std::move(cone_angles), {run.cones.size()});
  std::vector<std::string> kinds;
  for (const Uniformization& c : run.components) kinds.push_back(to_string(c.layout_kind));
  d["layout_kinds"] = kinds;
  if (!run.texture.vertex.empty()) {
    std::vector<double> flat;
    for (const auto& t : run.texture.vertex) flat.insert(flat.end(), {t.x(), t.y()});
    d["texcoord"] = numpy(std::move(flat), {run.texture.vertex.size(), 2});
  } else if (!run.texture.wedge.empty()) {
    std::vector<double> flat;
    for (const auto& face : run.texture.wedge) {
      for (const auto& t : face) flat.insert(flat.end(), {t.x(), t.y()});
    }
    d["texcoord"] = numpy(std::move(flat), {run.texture.wedge.size(), 3, 2});
  } else {
    d["texcoord"] = nb::none();
  }
  return d;
}

// The path comes as bytes (os.fsencode): file names in any encoding reach the reader as they are.
nb::tuple read_mesh_arrays(const nb::bytes& path_bytes) {
  const std::string path(path_bytes.c_str(), path_bytes.size());
  MeshFile file;
  {
    nb::gil_scoped_release released;
    file = read_mesh_file(path);
  }
  return nb::make_tuple(points(file.positions), triangles(file.triangles));
}

// The command on one file with flags; "" when it wrote its result, else the error it would print.
std::string run_file(const std::vector<std::string>& args) {
  const std::vector<const char*> argv = argv_of(args);
  const cli::Options o = cli::parse_options(static_cast<int>(argv.size()), argv.data());
  nb::gil_scoped_release released;
  try {
    cli::run(o);
  } catch (const std::exception& e) {
    return failure_message(e);
  }
  return "";
}

int run_command_line(const std::vector<std::string>& args) {
  const std::vector<const char*> argv = argv_of(args);
  nb::gil_scoped_release released;
  const int code = cli::run_command_line(static_cast<int>(argv.size()), argv.data());
  std::fflush(nullptr);  // the caller may end the process without C's exit handlers
  return code;
}

// One clean mesh (one component, no repairs) and its flow, kept between solves: the
// triangulation as flipped, u, the Hessian's pattern and symbolic analysis. Not for several
// Python threads at once (a solve runs without the GIL).
class Solver {
 public:
  Solver(const Points& v, const Triangles& f, std::vector<std::string> flags)
      : mesh_(to_points(v), to_triangles(f)) {
    const cli::Options o = parse("ricci_flow.Solver", std::move(flags));
    if (o.request.preset == TargetPreset::Values || !o.cones_file.empty() ||
        o.request.preset == TargetPreset::UnitDisk) {
      throw InvalidArgumentError(
          "a Solver is made with a geometry and a scheme; give targets to solve()");
    }
    const UniformizationOptions request = cli::request_for(o, mesh_.num_vertices());
    geometry_ = request.geometry.value_or(automatic_preset(mesh_).second);
    options_ = request.flow;
    scheme_ = request.scheme;
    structure_ =
        prepare_flow(mesh_, geometry_, scheme_, TargetCurvature::free_boundary_or_zero(mesh_));
    solver_ = std::make_unique<RicciFlowSolver>(mesh_, structure_, options_);
  }

  nb::dict solve(const Values& values) {
    if (values.shape(0) != static_cast<size_t>(mesh_.num_vertices())) {
      throw InvalidArgumentError("solve: " + std::to_string(values.shape(0)) + " values for " +
                                 std::to_string(mesh_.num_vertices()) + " vertices");
    }
    Eigen::VectorXd kbar(mesh_.num_vertices());
    for (int i = 0; i < kbar.size(); ++i) kbar[i] = values(static_cast<size_t>(i));
    const TargetCurvature target = TargetCurvature::from_values(mesh_, kbar);
    FlowResult r;
    {
      nb::gil_scoped_release released;
      r = solver_->solve(target);
    }
    nb::dict d;
    d["converged"] = r.converged;
    d["failure"] = r.failure;
    d["u"] = vector(r.u);
    d["curvature"] = vector(r.curvature);
    d["iterations"] = r.iterations;
    d["residual"] = r.residual;
    d["edge_flips"] = r.num_flips;
    d["symbolic_analyses"] = r.num_analyses;
    d["numeric_factorizations"] = r.num_factorizations;
    return d;
  }

  int num_vertices() const { return mesh_.num_vertices(); }
  std::string geometry() const { return to_string(geometry_); }

 private:
  CompactMesh mesh_;
  Geometry geometry_ = Geometry::Euclidean;
  SchemeOptions scheme_;
  FlowOptions options_;
  ConformalStructure structure_;
  std::unique_ptr<RicciFlowSolver> solver_;
};

}  // namespace

NB_MODULE(_ricci_flow, m) {
  m.doc() = "Unified discrete surface Ricci flow (compiled part of ricci_flow)";
  static nb::exception<ricci::Error> error(m, "RicciFlowError", PyExc_RuntimeError);
  nb::register_exception_translator([](const std::exception_ptr& p, void*) {
    try {
      std::rethrow_exception(p);
    } catch (const ricci::InvalidArgumentError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const ricci::InvalidTargetError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const ricci::InvalidMeshError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const ricci::IoError& e) {
      // Its message names the path in the file system's bytes: decoded as os.fsdecode does.
      PyObject* message = PyUnicode_DecodeFSDefault(e.what());
      if (!message) return;  // the decoding's own error stands
      PyErr_SetObject(PyExc_OSError, message);
      Py_DECREF(message);
    }
  });
  m.def("run_command_line", &run_command_line, nb::arg("args"),
        "Runs the ricci-flow command with args (args[0] the program's name); returns its exit "
        "code, C's stdio flushed.");
  m.def("run_file", &run_file, nb::arg("args"),
        "Runs the ricci-flow command on one file (args as for run_command_line); returns \"\" when "
        "it wrote its result, else its error message. Usage errors raise ValueError.");
  m.def("read_mesh", &read_mesh_arrays, nb::arg("path"),
        "Vertices (n, 3) and triangles (m, 3) of a mesh file (.off .obj .ply .stl .gii), polygons "
        "split as fans from their first corner.");
  m.def("uniformize", &uniformize_arrays, nb::arg("vertices"), nb::arg("faces"), nb::arg("flags"),
        "The uniformization of arrays with the command line tool's flags.");
  nb::class_<Solver>(m, "Solver")
      .def(nb::init<const Points&, const Triangles&, std::vector<std::string>>(),
           nb::arg("vertices"), nb::arg("faces"), nb::arg("flags"))
      .def("solve", &Solver::solve, nb::arg("target"))
      .def_prop_ro("num_vertices", &Solver::num_vertices)
      .def_prop_ro("geometry", &Solver::geometry);
}
