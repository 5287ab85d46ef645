// ricci-flow end to end: the PLY contract read back by an independent reader, the report, and
// every kind of bad input answered by one message and a non-zero exit.
#include <sys/stat.h>
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

#include "cli_run.h"
#include "ply_reader.h"
#include "ricci/mesh/geometry.h"
#include "test_meshes.h"

using ricci::kPi;

namespace {

using namespace ricci::test::cli;

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
  // Cones inside the surface: no layout in one piece draws them (a torus with these two came back
  // as a "flat torus" of closure error 2.3 before 2026-12-07); the atlas cuts seams through them.
  write_file(cones, "0 270\n80 450\n");
  r = ricci_flow(cgal("pipe.off") + " -o " + out + " --target cones:" + cones);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cone at vertex 0: 270 degrees inside the surface"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--target atlas --cones FILE"), std::string::npos) << r.err;
  r = ricci_flow(cgal("pipe.off") + " -o " + out + " --target atlas --cones " + cones);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // Cones of 450 and 270 degrees as --target FILE of curvatures (Kbar = 2 pi - angle: -pi/2 and
  // pi/2): the same refusal (laid out in one piece before 2026-12-07).
  std::string values;
  for (int v = 0; v < ricci::test::cgal_mesh("pipe.off").num_vertices(); ++v) {
    values += v == 0 ? "-1.5707963267948966\n" : v == 80 ? "1.5707963267948966\n" : "0\n";
  }
  const std::string kbar = temp("kbar.txt");
  write_file(kbar, values);
  r = ricci_flow(cgal("pipe.off") + " -o " + out + " --target " + kbar);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("target curvature at vertex 0: -1.570796327 (a cone of 450 degrees) inside "
                       "the surface"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--target atlas --cones FILE"), std::string::npos) << r.err;
  // Where no layout is drawn the metric alone is given: Kbar -1 at a vertex of the torus asks for
  // S2 (Gauss-Bonnet), which lays out no surface of genus 1.
  std::string sphere_values = "-1\n";
  for (int v = 1; v < ricci::test::cgal_mesh("pipe.off").num_vertices(); ++v)
    sphere_values += "0\n";
  write_file(kbar, sphere_values);
  r = ricci_flow(cgal("pipe.off") + " -o " + out + " --target " + kbar);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("No layout: a closed genus-1 surface in spherical geometry"),
            std::string::npos)
      << r.out;
  // Two tori in one file: the refusal names the vertex as the file numbers it (the second
  // torus's own vertex 5 is the file's 165; named 5 before 2026-12-07).
  const ricci::CompactMesh torus = ricci::test::cgal_mesh("pipe.off");
  std::ostringstream two;
  two << "OFF\n" << 2 * torus.num_vertices() << " " << 2 * torus.num_faces() << " 0\n";
  for (int copy = 0; copy < 2; ++copy) {
    for (const Eigen::Vector3d& p : torus.positions()) {
      two << p.x() + 10 * copy << " " << p.y() << " " << p.z() << "\n";
    }
  }
  for (int copy = 0; copy < 2; ++copy) {
    for (const auto& f : torus.faces()) {
      two << "3";
      for (int v : f) two << " " << v + copy * torus.num_vertices();
      two << "\n";
    }
  }
  const std::string tori = temp("two-tori.off");
  write_file(tori, two.str());
  const int second = torus.num_vertices() + 5;
  write_file(cones, std::to_string(second) + " 300\n");
  r = ricci_flow(tori + " -o " + out + " --target cones:" + cones);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cone at vertex " + std::to_string(second) + ": 300 degrees"),
            std::string::npos)
      << r.err;
  std::string second_values;
  for (int v = 0; v < 2 * torus.num_vertices(); ++v) second_values += v == second ? "1\n" : "0\n";
  write_file(kbar, second_values);
  r = ricci_flow(tori + " -o " + out + " --target " + kbar);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("target curvature at vertex " + std::to_string(second) + ": 1 "),
            std::string::npos)
      << r.err;
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
  // A file name in another encoding (Latin-1's e acute) and with a control character: the report
  // is JSON all the same, the name's undecodable byte as U+FFFD.
  const std::string odd = temp("caf\xe9\x01.off"), report = temp("odd.json");
  std::ofstream(odd, std::ios::binary) << slurp(cgal("nefertiti.off"));
  ricci_flow("'" + odd + "' -o " + temp("odd.ply") + " --report " + report);
  EXPECT_TRUE(parses_as_json(report)) << slurp(report);
  EXPECT_NE(slurp(report).find("caf\\ufffd\\u0001.off"), std::string::npos) << slurp(report);
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

#ifndef RICCI_SANITIZED  // the sanitizers reserve more address space than the limit below
TEST(Cli, OutOfMemorySaysSoAndEnds) {
  // An address space of 90 MB, of which the program and its libraries take about 55, and
  // OpenBLAS's one worker thread (OPENBLAS_NUM_THREADS=2: the caller's and one more, whatever the
  // cores; with a stack of 8 MB) about 9 more: too little for that worker's buffer, which it then
  // asks for without end, and OpenBLAS's exit handler waits for it. Before, the process never
  // ended: not even `--version`. OpenFOAM's motorbike (10.7 MB of OBJ, 331,653 faces) needs far
  // more; its message was "std::bad_alloc". (A file could also be read cut short where memory ran
  // out: pymeshfix's bunny as a 100k-face OBJ, at 70 MB, failed with "a vertex needs three
  // coordinates" on a line the file has whole.)
  const std::string limited =
      "ulimit -v 90000; ulimit -s 8192; OPENBLAS_NUM_THREADS=2 timeout 120 " +
      std::string(RICCI_CLI_PATH) + " ";
  const std::string out = temp("oom.ply"), err = temp("oom.err"), said = temp("oom.out");
  std::remove(out.c_str());
  const int version = std::system(("(" + limited + "--version) >" + said + " 2>" + err).c_str());
  ASSERT_TRUE(WIFEXITED(version)) << version;
  EXPECT_EQ(WEXITSTATUS(version), 0) << slurp(err);  // timeout's 124: the process did not end
  EXPECT_EQ(slurp(said), "ricci-flow 0.1.0\n");
  const std::string motorbike = std::string(RICCI_REAL_MESH_DIR) + "/openfoam-motorbike.obj";
  const int status =
      std::system(("(" + limited + motorbike + " -o " + out + ") >" + said + " 2>" + err).c_str());
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 1) << slurp(err);
  EXPECT_NE(slurp(err).find("ricci-flow: error: out of memory"), std::string::npos) << slurp(err);
  EXPECT_FALSE(std::ifstream(out).good());
}
#endif

TEST(Cli, FailedRunWritesNoMesh) {
  const std::string out = temp("never.ply");
  std::remove(out.c_str());
  const CliRun r = ricci_flow(cgal("elk.off") + " -o " + out +
                              " --scheme yamabe --no-flips --report " + temp("never.json"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_FALSE(std::ifstream(out).good());
  EXPECT_NE(slurp(temp("never.json")).find("\"converged\": false"), std::string::npos);
  // A converged run whose picture cannot be written leaves no mesh either, and no temporary.
  const CliRun pictured =
      ricci_flow(cgal("nefertiti.off") + " -o " + out + " --picture /nonexistent-folder/p.png");
  EXPECT_EQ(pictured.exit_code, 1) << pictured.err;
  EXPECT_NE(pictured.err.find("cannot write '/nonexistent-folder/p.png'"), std::string::npos)
      << pictured.err;
  EXPECT_FALSE(std::ifstream(out).good());
  // A write that fails part way (past a file size limit of 1 KiB) leaves nothing either.
  const int limited = std::system(("(ulimit -f 1; " + std::string(RICCI_CLI_PATH) + " " +
                                   cgal("nefertiti.off") + " -o " + out + ") 2>/dev/null")
                                      .c_str());
  EXPECT_TRUE(WIFEXITED(limited) && WEXITSTATUS(limited) == 1) << limited;
  EXPECT_FALSE(std::ifstream(out).good());
  // No temporary of this test's outputs is left (other tests write beside them meanwhile).
  EXPECT_NE(std::system(("ls " + out + ".ricci-flow-*.part >/dev/null 2>&1").c_str()), 0)
      << "a temporary output of " << out << " was left";
  // Outputs that are no regular file are written to directly (not replaced by a renamed file), and
  // two outputs of one name are refused.
  const CliRun to_null = ricci_flow(cgal("nefertiti.off") + " -o /dev/null --report /dev/null");
  EXPECT_EQ(to_null.exit_code, 0) << to_null.err;
  struct stat null_status {};
  EXPECT_EQ(stat("/dev/null", &null_status), 0);
  EXPECT_TRUE(S_ISCHR(null_status.st_mode)) << "/dev/null is no longer a device";
  const CliRun twice = ricci_flow(cgal("nefertiti.off") + " -o " + out + " --picture " + out);
  EXPECT_EQ(twice.exit_code, 1);
  EXPECT_NE(twice.err.find("twice"), std::string::npos) << twice.err;
  EXPECT_FALSE(std::ifstream(out).good());
}

}  // namespace
