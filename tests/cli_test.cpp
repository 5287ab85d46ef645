// ricci-flow end to end: the PLY contract read back by an independent reader, the report, and
// every kind of bad input answered by one message and a non-zero exit.
#include <sys/wait.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ply_reader.h"
#include "ricci/geometry.h"
#include "test_meshes.h"

using ricci::kPi;

namespace {

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Per-test file names: ctest runs the tests of this file in parallel processes.
std::string temp(const std::string& name) {
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  return ::testing::TempDir() + "/ricci_cli_" + test->name() + "_" + name;
}

CliRun ricci_flow(const std::string& args) {
  const std::string out = temp("stdout.txt"), err = temp("stderr.txt");
  const std::string cmd =
      std::string(RICCI_CLI_PATH) + " " + args + " >" + out + " 2>" + err + " </dev/null";
  const int status = std::system(cmd.c_str());
  CliRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

std::string cgal(const std::string& name) {
  return ricci::test::cgal_mesh_path(name);
}

using ricci::test::read_ply;

void write_file(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

TEST(Cli, DiskResultFollowsThePlyContract) {
  const std::string out = temp("disk.ply"), report = temp("disk.json"), png = temp("disk.png");
  const CliRun r = ricci_flow(cgal("nefertiti.off") + " -o " + out + " --report " + report +
                              " --picture " + png + " --target free-boundary");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Converged in"), std::string::npos) << r.out;
  const ricci::test::PlyData ply = read_ply(out);
  const std::vector<std::string> expected = {"x",
                                             "y",
                                             "z",
                                             "ricci_u",
                                             "ricci_radius",
                                             "ricci_curvature",
                                             "ricci_target",
                                             "layout_x",
                                             "layout_y",
                                             "layout_z",
                                             "texture_u",
                                             "texture_v"};
  EXPECT_EQ(ply.vertex_properties, expected);
  const ricci::CompactMesh mesh = ricci::test::cgal_mesh("nefertiti.off");
  ASSERT_EQ(ply.vertex.at("x").size(), static_cast<size_t>(mesh.num_vertices()));
  ASSERT_EQ(ply.faces.size(), static_cast<size_t>(mesh.num_faces()));
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    EXPECT_EQ(ply.vertex.at("x")[v], mesh.positions()[v].x());  // coordinates unchanged
    const double target = ply.vertex.at("ricci_target")[v];
    EXPECT_EQ(std::isnan(target), mesh.is_boundary_vertex(v));
    if (!mesh.is_boundary_vertex(v)) {
      EXPECT_NEAR(ply.vertex.at("ricci_curvature")[v], 0.0, 1e-9);
    }
    EXPECT_EQ(ply.vertex.at("layout_z")[v], 0.0);
    EXPECT_GE(ply.vertex.at("texture_u")[v], 0.0);
    EXPECT_LE(ply.vertex.at("texture_v")[v], 1.0);
  }
  // The layout realises the flat metric: interior angle sums of the laid-out triangles are 2 pi.
  std::vector<double> angle_sum(mesh.num_vertices(), 0.0);
  for (const auto& t : ply.faces) {
    for (int c = 0; c < 3; ++c) {
      const int a = t[c], b = t[(c + 1) % 3], d = t[(c + 2) % 3];
      const double ux = ply.vertex.at("layout_x")[b] - ply.vertex.at("layout_x")[a];
      const double uy = ply.vertex.at("layout_y")[b] - ply.vertex.at("layout_y")[a];
      const double vx = ply.vertex.at("layout_x")[d] - ply.vertex.at("layout_x")[a];
      const double vy = ply.vertex.at("layout_y")[d] - ply.vertex.at("layout_y")[a];
      EXPECT_GT(ux * vy - uy * vx, 0.0) << "flipped triangle";
      angle_sum[a] += std::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
    }
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!mesh.is_boundary_vertex(v)) {
      EXPECT_NEAR(angle_sum[v], 2 * kPi, 1e-8);
    }
  }
  const std::string json = slurp(report);
  for (const char* key :
       {"\"converged\": true", "\"residual_history\"", "\"seconds\"", "\"gauss_bonnet_error\"",
        "\"flipped_faces\": 0", "\"collapsed_faces\": 0", "\"failure\": null", "\"edge_flips\": ",
        "\"symbolic_analyses\": ", "\"edge_flips_needed\": false", "\"repairs\": []"}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << " missing in " << json;
  }
  const std::string picture = slurp(png);
  ASSERT_GT(picture.size(), 8u);
  EXPECT_EQ(picture.substr(1, 3), "PNG");
}

TEST(Cli, ClosedSurfacesInTheirOwnGeometry) {
  struct Case {
    std::string mesh, geometry;
  };
  for (const Case& c : {Case{"sphere.off", "spherical"}, Case{"eight.off", "hyperbolic"},
                        Case{"pipe.off", "euclidean"}}) {
    const std::string out = temp("closed.ply");
    // On the input triangulation (these smooth meshes need no flips) no input face is turned
    // over; with flips, input faces whose edges were flipped can be (pipe.off: 17 of 320).
    const CliRun r =
        ricci_flow(cgal(c.mesh) + " -o " + out + " --scheme inversive-distance --no-flips");
    ASSERT_EQ(r.exit_code, 0) << c.mesh << ": " << r.err;
    EXPECT_NE(r.out.find(c.geometry + " geometry"), std::string::npos)
        << r.out;  // auto by topology
    EXPECT_NE(r.out.find(" 0 of the input's faces flipped"), std::string::npos) << r.out;
    const ricci::test::PlyData ply = read_ply(out);
    for (double k : ply.vertex.at("ricci_curvature")) EXPECT_NEAR(k, 0.0, 1e-9);
    if (c.geometry == "spherical") {
      // On the unit sphere, centred by a Moebius map; no texture.
      ASSERT_TRUE(ply.has_vertex("layout_z"));
      EXPECT_TRUE(ply.face_texcoords.empty());
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (size_t v = 0; v < ply.vertex.at("layout_x").size(); ++v) {
        const Eigen::Vector3d x(ply.vertex.at("layout_x")[v], ply.vertex.at("layout_y")[v],
                                ply.vertex.at("layout_z")[v]);
        EXPECT_NEAR(x.norm(), 1.0, 1e-12);
        centroid += x;
      }
      EXPECT_LE(centroid.norm(), 1e-9);
    } else {
      // Cut open: per-face (wedge) texture coordinates, six per face, in the unit square.
      EXPECT_FALSE(ply.has_vertex("layout_x"));
      ASSERT_EQ(ply.face_texcoords.size(), ply.faces.size());
      for (const auto& t : ply.face_texcoords) {
        ASSERT_EQ(t.size(), 6u);
        for (double x : t) {
          EXPECT_GE(x, 0.0);
          EXPECT_LE(x, 1.0);
        }
      }
    }
  }
}

TEST(Cli, AutoTargetLaysOutEveryTopology) {
  struct Case {
    std::string mesh, kind;
  };
  for (const Case& c :
       {Case{"nefertiti.off", "plane"}, Case{"head.off", "plane"}, Case{"sphere.off", "sphere"},
        Case{"pipe.off", "plane-cut"}, Case{"eight.off", "poincare-disk"}}) {
    const std::string out = temp("auto.ply"), report = temp("auto.json");
    const CliRun r = ricci_flow(cgal(c.mesh) + " -o " + out + " --report " + report);
    ASSERT_EQ(r.exit_code, 0) << c.mesh << ": " << r.err;
    const std::string json = slurp(report);
    EXPECT_NE(json.find("\"kind\": \"" + c.kind + "\""), std::string::npos) << c.mesh << json;
    for (const char* key : {"\"quasi_conformal\": {\"median\": ", "\"area_ratio\": {\"p5\": ",
                            "\"max_abs_curvature_error\": "}) {
      EXPECT_NE(json.find(key), std::string::npos) << c.mesh << ": " << key << " missing";
    }
    const ricci::test::PlyData ply = read_ply(out);
    if (c.kind == "plane") {
      // A disk onto the unit disk, head.off's three boundary loops onto circles in it.
      EXPECT_NE(json.find("\"preset\": \"disk\""), std::string::npos) << json;
      const ricci::CompactMesh mesh = ricci::test::cgal_mesh(c.mesh);
      double outer = 0;
      for (int v = 0; v < mesh.num_vertices(); ++v) {
        const double r2 = std::hypot(ply.vertex.at("layout_x")[v], ply.vertex.at("layout_y")[v]);
        EXPECT_LE(r2, 1.0 + 1e-7) << c.mesh;
        outer = std::max(outer, r2);
      }
      EXPECT_NEAR(outer, 1.0, 1e-7) << c.mesh;
    } else if (c.kind != "sphere") {
      EXPECT_EQ(ply.face_texcoords.size(), ply.faces.size()) << c.mesh;
      EXPECT_NE(json.find("\"relation_error\": "), std::string::npos) << json;
    }
  }
}

TEST(Cli, ConesFileAndDiskNormalization) {
  const ricci::CompactMesh mesh = ricci::test::cgal_mesh("nefertiti.off");
  const std::vector<int>& loop = mesh.boundary_loops()[0];
  const std::string cones = temp("cones.txt"), out = temp("cones.ply");
  std::string text = "# vertex angle_degrees\n";
  for (size_t k = 0; k < 4; ++k) text += std::to_string(loop[k * loop.size() / 4]) + " 90\n";
  write_file(cones, text);
  CliRun r = ricci_flow(cgal("nefertiti.off") + " -o " + out + " --target cones:" + cones);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("euclidean geometry"), std::string::npos) << r.out;
  write_file(cones, "12 ninety\n");
  r = ricci_flow(cgal("nefertiti.off") + " -o " + out + " --target cones:" + cones);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(":1: '12 ninety' is not 'VERTEX ANGLE_DEGREES'"), std::string::npos)
      << r.err;

  int interior = 0;
  while (mesh.is_boundary_vertex(interior)) ++interior;
  r = ricci_flow(cgal("nefertiti.off") + " -o " + out + " --target disk --center " +
                 std::to_string(interior) + " --axis " + std::to_string(loop[0]));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const ricci::test::PlyData ply = read_ply(out);
  EXPECT_NEAR(ply.vertex.at("layout_x")[interior], 0.0, 1e-12);
  EXPECT_NEAR(ply.vertex.at("layout_y")[interior], 0.0, 1e-12);
  EXPECT_NEAR(ply.vertex.at("layout_x")[loop[0]], 1.0, 1e-8);
  EXPECT_NEAR(ply.vertex.at("layout_y")[loop[0]], 0.0, 1e-12);
  r = ricci_flow(cgal("pipe.off") + " -o " + out + " --center 3");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("needs the disk target"), std::string::npos) << r.err;
}

TEST(Cli, MixedSchemeReadsEpsFileAndTargetFile) {
  const ricci::CompactMesh mesh = ricci::test::cgal_mesh("nefertiti.off");
  std::string eps, target;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    eps += std::to_string(v % 3 - 1) + "\n";
    target += mesh.is_boundary_vertex(v) ? "nan\n" : "0\n";
  }
  write_file(temp("eps.txt"), eps);
  write_file(temp("target.txt"), "# Kbar per vertex\n" + target);
  const CliRun r =
      ricci_flow(cgal("nefertiti.off") + " -o " + temp("mixed.ply") + " --scheme mixed --eps " +
                 temp("eps.txt") + " --target " + temp("target.txt") + " --solver ldlt --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
}

// --- bad input: exit status and one message naming the problem

void expect_error(const std::string& args, int code, const std::vector<std::string>& words) {
  const CliRun r = ricci_flow(args);
  EXPECT_EQ(r.exit_code, code) << args << "\n" << r.err;
  for (const auto& w : words)
    EXPECT_NE(r.err.find(w), std::string::npos) << "'" << w << "' not in: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
}

TEST(Cli, BadInputGetsAClearError) {
  const std::string out = " -o " + temp("bad.ply");
  expect_error(cgal("no-such-mesh.off") + out, 1, {"cannot open", "no-such-mesh.off"});
  // Usage errors (exit 2) are found before the mesh is read: a missing mesh does not hide them.
  expect_error(cgal("no-such-mesh.off") + out + " --scheme ricci", 2, {"unknown scheme"});
  expect_error(cgal("nefertiti.off"), 2, {"-o OUTPUT.ply"});
  expect_error(cgal("nefertiti.off") + out + " --scheme ricci", 2, {"unknown scheme 'ricci'"});
  expect_error(cgal("nefertiti.off") + out + " --frobnicate", 2, {"unknown option '--frobnicate'"});
  expect_error(cgal("nefertiti.off") + out + " --tolerance abc", 2,
               {"--tolerance expects a finite number"});
  expect_error(cgal("nefertiti.off") + out + " --scheme mixed", 2, {"needs --eps FILE"});
  expect_error(cgal("nefertiti.off") + out + " --angle 120 --scheme thurston", 2,
               {"outside [0, 90]"});
  expect_error(cgal("nefertiti.off") + out + " --solver umfpack", 2, {"unknown linear solver"});
  // Topology and geometry
  expect_error(cgal("pipe.off") + out + " --geometry spherical", 1,
               {"spherical geometry needs", "genus 1"});
  expect_error(cgal("sphere.off") + out + " --geometry hyperbolic", 1,
               {"hyperbolic geometry needs"});
  expect_error(cgal("sphere.off") + out + " --target free-boundary", 1, {"needs a boundary"});
  expect_error(cgal("sphere.off") + out + " --picture " + temp("x.png"), 1,
               {"--picture needs a layout in the plane"});
  // PyVista's airplane (real-mesh set): the automatic target gives component 0's circle domain,
  // squeezed below double precision, the free boundary, cut open.
  expect_error(std::string(RICCI_REAL_MESH_DIR) + "/pyvista-airplane.ply" + out + " --picture " +
                   temp("x.png"),
               1, {"--picture needs a layout in the plane with one position per vertex"});
  expect_error(cgal("blobby_3cc.off") + out + " --strict", 1,
               {"3 connected components", "blobby_3cc.off"});
  expect_error(cgal("nefertiti.off") + out + " --target zero", 1, {"Gauss-Bonnet fails"});
  // Targets from a file
  write_file(temp("short.txt"), "0\n0\n");
  expect_error(cgal("nefertiti.off") + out + " --target " + temp("short.txt"), 1,
               {"2 values for a mesh of 299 vertices"});
  std::string big;
  for (int v = 0; v < 160; ++v) big += (v == 5 ? "7\n" : "0\n");
  write_file(temp("big.txt"), big);
  expect_error(cgal("pipe.off") + out + " --target " + temp("big.txt"), 1,
               {"vertex 5", "Kbar < 2 pi"});
  write_file(temp("word.txt"), "0\nzero\n");
  expect_error(cgal("nefertiti.off") + out + " --target " + temp("word.txt"), 1,
               {"word.txt:2", "'zero' is not a number"});
  // Broken meshes written as OFF files, refused with --strict (repaired by default: below)
  write_file(temp("nonmanifold.off"),
             "OFF\n5 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n3 0 1 2\n3 0 2 3\n3 2 0 4\n");
  expect_error(temp("nonmanifold.off") + out + " --strict", 1,
               {"non-manifold edges", "edge (0, 2)"});
  write_file(temp("bowtie.off"),
             "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n-1 0 0\n-1 -1 0\n3 0 1 2\n3 0 3 4\n");
  expect_error(temp("bowtie.off") + out + " --strict", 1, {"non-manifold vertices", "vertex 0"});
  write_file(temp("degenerate.off"), "OFF\n4 2 0\n0 0 0\n1 0 0\n2 0 0\n0 1 0\n3 0 1 2\n3 0 1 3\n");
  expect_error(temp("degenerate.off") + out + " --strict", 1, {"degenerate faces", "face 0"});
  write_file(temp("duplicate.off"),
             "OFF\n4 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n3 1 2 0\n");
  expect_error(temp("duplicate.off") + out + " --strict", 1, {"duplicate faces"});
  write_file(temp("unreferenced.off"),
             "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n9 9 9\n3 0 1 2\n3 0 2 3\n");
  expect_error(temp("unreferenced.off") + out + " --strict", 1,
               {"unreferenced vertices", "vertex 4"});
  write_file(temp("nan.off"), "OFF\n4 2 0\n0 0 0\n1 0 0\nnan 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
  expect_error(temp("nan.off") + out, 1, {"NaN or infinite", "vertex 2"});
  // A flow that cannot converge on this triangulation
  expect_error(cgal("elk.off") + out + " --scheme yamabe --no-flips", 1,
               {"stalled at iteration", "degenerat"});
  expect_error(cgal("nefertiti.off") + out + " --max-iterations 1", 1,
               {"no convergence in 1 iterations"});
}

bool parses_as_json(const std::string& path) {
  // An independent parser: Python's.
  return std::system(("python3 -c 'import json, sys; json.load(open(sys.argv[1]))' " + path +
                      " >/dev/null 2>&1")
                         .c_str()) == 0;
}

TEST(Cli, ReportsAreJsonForOneAndSeveralComponents) {
  for (const char* mesh : {"nefertiti.off", "blobby_3cc.off"}) {
    const std::string report = temp("report.json");
    std::remove(report.c_str());
    ricci_flow(cgal(mesh) + " -o " + temp("report.ply") + " --report " + report +
               " --scheme tangential");
    EXPECT_TRUE(parses_as_json(report)) << mesh << ": " << slurp(report);
  }
}

TEST(Cli, DirtyMeshesAreRepairedAndReported) {
  // The defects --strict refuses (above) are repaired by default, keeping the surface, and said.
  struct Case {
    std::string name, off, repaired;
    int vertices, faces;  // of the result
  };
  for (const Case& c : {
           Case{"nonmanifold",
                "5 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n3 0 1 2\n3 0 2 3\n3 2 0 4\n",
                "1 non-manifold edges cut open", 7, 3},
           Case{"bowtie", "5 2 0\n0 0 0\n1 0 0\n1 1 0\n-1 0 0\n-1 -1 0\n3 0 1 2\n3 0 3 4\n",
                "1 non-manifold vertices split", 6, 2},
           Case{"degenerate", "4 2 0\n0 0 0\n1 0 0\n2 0 0\n0 1 0\n3 0 1 2\n3 0 1 3\n",
                "1 zero-area faces removed", 4, 1},
           Case{"duplicate", "4 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n3 1 2 0\n",
                "1 duplicate faces dropped (first: face 2)", 4, 2},
           Case{"unreferenced", "5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n9 9 9\n3 0 1 2\n3 0 2 3\n",
                "1 unreferenced vertices kept without a result (first: vertex 4)", 5, 2},
           // Vertex 0 in no face, as in OBJ files whose first vertex nothing uses: the UVs must
           // stay with their vertices.
           Case{"unreferenced-first",
                "5 2 0\n9 9 9\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 1 2 3\n3 1 3 4\n",
                "1 unreferenced vertices kept without a result (first: vertex 0)", 5, 2},
           Case{"misoriented", "4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 3 2\n",
                "1 faces reoriented", 4, 2},
       }) {
    write_file(temp(c.name + ".off"), "OFF\n" + c.off);
    const std::string out = temp(c.name + "-repaired.ply");
    const CliRun r = ricci_flow(temp(c.name + ".off") + " -o " + out);
    ASSERT_EQ(r.exit_code, 0) << c.name << ": " << r.err;
    EXPECT_NE(r.out.find("Repaired: " + c.repaired), std::string::npos) << c.name << r.out;
    const ricci::test::PlyData ply = read_ply(out);
    EXPECT_EQ(ply.vertex.at("x").size(), static_cast<size_t>(c.vertices)) << c.name;
    EXPECT_EQ(ply.faces.size(), static_cast<size_t>(c.faces)) << c.name;
    // The input's vertices keep their place; every face is laid out counter-clockwise.
    EXPECT_EQ(ply.vertex.at("x")[1], c.name == "unreferenced-first" ? 0.0 : 1.0) << c.name;
    for (const auto& f : ply.faces) {
      const auto uv = [&](int k) {
        return std::array<double, 2>{ply.vertex.at("texture_u")[f[k]],
                                     ply.vertex.at("texture_v")[f[k]]};
      };
      const auto a = uv(0), b = uv(1), d = uv(2);
      EXPECT_GT((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]), 0) << c.name;
    }
  }
}

TEST(Cli, RealDirtyMeshesAsTheyCome) {
  // From meshes/real-meshes.tsv (origins and licences there): an ASCII STL in capitals, an OBJ
  // with negative indices and quads, one with 16-gons, one with a non-manifold edge, one with
  // non-manifold vertices and misoriented faces, and STL faces back to back.
  const std::string dir = RICCI_REAL_MESH_DIR;
  for (const char* mesh :
       {"admesh-block.stl", "uranium-negative-indices.obj", "bouncy-farmer.obj",
        "minetest-chest-open.obj", "geomview-hook.off", "openscad-back-to-back.stl"}) {
    const std::string out = temp("real.ply");
    const CliRun r = ricci_flow(dir + "/" + mesh + " -o " + out);
    EXPECT_EQ(r.exit_code, 0) << mesh << ": " << r.err;
    if (r.exit_code != 0) continue;
    // Every face laid out counter-clockwise: in the plane, or seen from outside the sphere, or
    // in the texture of a surface cut open.
    const ricci::test::PlyData ply = read_ply(out);
    for (size_t k = 0; k < ply.faces.size(); ++k) {
      const auto& f = ply.faces[k];
      std::array<Eigen::Vector3d, 3> p;
      for (int c = 0; c < 3; ++c) {
        p[c] = ply.has_vertex("layout_x") ? Eigen::Vector3d(ply.vertex.at("layout_x")[f[c]],
                                                            ply.vertex.at("layout_y")[f[c]],
                                                            ply.vertex.at("layout_z")[f[c]])
                                          : Eigen::Vector3d(ply.face_texcoords[k][2 * c],
                                                            ply.face_texcoords[k][2 * c + 1], 0.0);
      }
      const bool plane = p[0].z() == 0 && p[1].z() == 0 && p[2].z() == 0;
      const double orientation =
          plane ? (p[1] - p[0]).cross(p[2] - p[0]).z() : p[0].dot(p[1].cross(p[2]));
      EXPECT_GT(orientation, 0) << mesh << " face " << k;
    }
  }
  // Closed genus-0 surfaces in S2: the ipp-3d scan converges (its punctured flow walks to the
  // puncture's shifted u with flips); so do the parts of assimp's spider, whose Delaunay
  // triangulations need two edges between one pair of vertices.
  const CliRun ipp = ricci_flow(dir + "/ipp-3d.stl -o " + temp("ipp.ply"));
  EXPECT_EQ(ipp.exit_code, 0) << ipp.err;
  const CliRun r = ricci_flow(dir + "/assimp-spider.obj -o " + temp("spider.ply"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// Where the Yamabe flow gives no map with either target (sumo-tram.obj's windowed bodies), the
// defaults deliver the tangential scheme's and say so, in the summary and the report (with
// --no-flips the tool refuses: FailedRunWritesNoMesh).
TEST(Cli, DefaultsSayWhenTheTangentialSchemeStandsInForYamabe) {
  const std::string tram = std::string(RICCI_REAL_MESH_DIR) + "/sumo-tram.obj";
  const CliRun r = ricci_flow(tram + " -o " + temp("tram.ply") + " --report " + temp("tram.json"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Warning: the tangential scheme instead of Yamabe: with the Yamabe scheme "
                       "the disk target was not reached"),
            std::string::npos)
      << r.out;
  const std::string report = slurp(temp("tram.json"));
  EXPECT_NE(report.find("\"scheme_instead\": \"with the Yamabe scheme"), std::string::npos);
  EXPECT_NE(report.find("\"scheme_instead\": null"), std::string::npos);  // the other components
}

// With flips that turn input faces over (elk.off, always flipping), the tool writes the common
// subdivision: the input's vertices first and unchanged, new ones on input faces at their
// barycentric coordinates, and no face turned over in the texture.
TEST(Cli, FlipsThatTurnInputFacesDeliverTheCommonSubdivision) {
  const ricci::CompactMesh mesh = ricci::test::cgal_mesh("elk.off");
  const std::string out = temp("elk-subdivision.ply");
  const CliRun r = ricci_flow(cgal("elk.off") + " -o " + out + " --flips always");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Common subdivision: "), std::string::npos) << r.out;
  const ricci::test::PlyData ply = ricci::test::read_ply(out);
  const std::vector<double>&x = ply.vertex.at("x"), &y = ply.vertex.at("y"),
        &z = ply.vertex.at("z");
  const size_t nv = static_cast<size_t>(mesh.num_vertices());
  ASSERT_GT(x.size(), nv);
  for (size_t v = 0; v < nv; ++v) {
    ASSERT_EQ(Eigen::Vector3d(x[v], y[v], z[v]), mesh.positions()[v]) << v;
  }
  ASSERT_TRUE(ply.has_vertex("ricci_input_face"));
  for (size_t v = nv; v < x.size(); ++v) {
    const int f = static_cast<int>(ply.vertex.at("ricci_input_face")[v]);
    ASSERT_GE(f, 0);
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      p += ply.vertex.at("ricci_bary_" + std::to_string(k))[v] *
           mesh.positions()[mesh.face_vertex(f, k)];
    }
    EXPECT_LE((p - Eigen::Vector3d(x[v], y[v], z[v])).norm(), 1e-9) << v;
  }
  ASSERT_EQ(ply.face_texcoords.size(), ply.faces.size());
  int turned = 0;
  for (const auto& t : ply.face_texcoords) {
    const double a = (t[2] - t[0]) * (t[5] - t[1]) - (t[3] - t[1]) * (t[4] - t[0]);
    turned += !(a > 0);
  }
  EXPECT_EQ(turned, 0);
  // The input's own triangulation kept: its faces turn over, and the run says so.
  const CliRun kept = ricci_flow(cgal("elk.off") + " -o " + temp("elk-kept.ply") +
                                 " --flips always --keep-input-triangulation");
  EXPECT_EQ(kept.exit_code, 1);
  EXPECT_NE(kept.err.find("of the input's faces are turned over"), std::string::npos) << kept.err;
}

// Poincare disk layouts that straight drawing would turn over: thin faces near the rim (Netgen's
// hinge, no flips) are split; a domain reaching hyperbolic distance 24 (CGAL's elephant with
// holes) is drawn in charts. Both exit 0 with every face counter-clockwise in the texture.
TEST(Cli, PoincareDiskLayoutsAreSplitOrChartedUntilNoFaceTurns) {
  for (const auto& [input, says] :
       {std::pair{std::string(RICCI_REAL_MESH_DIR) + "/netgen-hinge.stl",
                  "Poincare disk drawing: "},
        std::pair{cgal("elephant-with-holes.off"), "Poincare disk in "}}) {
    const std::string out = temp("poincare.ply");
    const CliRun r = ricci_flow(input + " -o " + out + " --report " + temp("poincare.json"));
    ASSERT_EQ(r.exit_code, 0) << input << ": " << r.err;
    EXPECT_NE(r.out.find(says), std::string::npos) << r.out;
    const ricci::test::PlyData ply = ricci::test::read_ply(out);
    ASSERT_EQ(ply.face_texcoords_double.size(), ply.faces.size());
    int turned = 0;
    for (const auto& t : ply.face_texcoords_double) {
      const double a = (t[2] - t[0]) * (t[5] - t[1]) - (t[3] - t[1]) * (t[4] - t[0]);
      turned += !(a > 0);
    }
    EXPECT_EQ(turned, 0) << input;
  }
}

TEST(Cli, FailedRunWritesNoMesh) {
  const std::string out = temp("never.ply");
  std::remove(out.c_str());
  const CliRun r = ricci_flow(cgal("elk.off") + " -o " + out +
                              " --scheme yamabe --no-flips --report " + temp("never.json"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_FALSE(std::ifstream(out).good());
  EXPECT_NE(slurp(temp("never.json")).find("\"converged\": false"), std::string::npos);
}

}  // namespace
