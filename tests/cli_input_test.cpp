// ricci-flow on the input side: every kind of bad input answered by one message and a non-zero
// exit; dirty and real meshes repaired as they come, and the repairs reported.
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
  // The atlas's options out of range, before the mesh is read (a budget of 0 read as none, a bound
  // of 0 refused by the placement with its own words, before 2026-12-07).
  const std::string atlas = cgal("no-such-mesh.off") + out + " --target atlas";
  expect_error(atlas + " --max-cones 0", 2, {"--max-cones expects an integer in [1, 1000000]"});
  expect_error(atlas + " --distortion 0", 2, {"--distortion expects a positive number, got '0'"});
  expect_error(atlas + " --distortion -0.1", 2, {"--distortion expects a positive number"});
  expect_error(atlas + " --texture-size 8", 2,
               {"--texture-size expects an integer in [16, 1000000], got '8'"});
  // The atlas's options where no atlas is asked for, refused as --eps is without the mixed scheme
  // (ignored before 2026-12-07); after --target atlas in any order they are taken.
  const std::string disk = cgal("no-such-mesh.off") + out;
  expect_error(disk + " --distortion 0.1", 2, {"--distortion is used only by --target atlas"});
  expect_error(disk + " --padding 2 --max-cones 8 --target zero", 2,
               {"--padding is used only by --target atlas"});
  expect_error(disk + " --cone-angles quarter --target atlas", 1, {"cannot open"});
  // The cones given twice or to a target that takes none, and a picture of an atlas: usage errors
  // (exit 1 once the mesh was read, before 2026-12-07).
  const std::string cones = temp("two-cones.txt");
  write_file(cones, "0 90\n");
  expect_error(disk + " --cones " + cones + " --target disk", 2,
               {"the cones are a target of their own, or the atlas's cones"});
  expect_error(disk + " --cones " + cones + " --target cones:" + cones, 2, {"give the cones once"});
  expect_error(disk + " --target atlas --picture " + temp("atlas.png"), 2,
               {"--picture draws a layout in the plane with one position per vertex, not an "
                "atlas's charts"});
  // No cones in the file: refused, not read as "place them".
  write_file(cones, "# none\n");
  expect_error(cgal("eight.off") + out + " --target atlas --cones " + cones, 1, {"no cones in it"});
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
  // A name the file system will not answer for (too long) is read as a file, and says so (exit
  // 134 from an exception, before it was caught).
  expect_error(cgal("nefertiti.off") + out + " --target " + std::string(300, 'a'), 1,
               {"cannot open"});
  expect_error(cgal("nefertiti.off") + out + " --target bogus", 2,
               {"--target 'bogus' is no target (auto, disk, free-boundary, zero, atlas"});
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

TEST(Cli, AMeshCutOpenIsSewnUnlessItsCutsAreKept) {
  // A cylinder cut along a line, its vertices there copied: the copies are joined by default (an
  // annulus, two boundary loops); with --keep-cuts the mesh is the disk it was cut to.
  const int around = 16, along = 6;
  std::ostringstream off;
  off << "OFF\n" << (around + 1) * (along + 1) << " " << 2 * around * along << " 0\n";
  for (int j = 0; j <= along; ++j) {
    for (int i = 0; i <= around; ++i) {
      const double a = 2 * kPi * (i % around) / around;  // column `around` lies on column 0
      off << std::cos(a) << " " << std::sin(a) << " " << 0.3 * j << "\n";
    }
  }
  const auto at = [&](int i, int j) { return j * (around + 1) + i; };
  for (int j = 0; j < along; ++j) {
    for (int i = 0; i < around; ++i) {
      off << "3 " << at(i, j) << " " << at(i + 1, j) << " " << at(i + 1, j + 1) << "\n";
      off << "3 " << at(i, j) << " " << at(i + 1, j + 1) << " " << at(i, j + 1) << "\n";
    }
  }
  write_file(temp("cut-cylinder.off"), off.str());
  const CliRun sewn = ricci_flow(temp("cut-cylinder.off") + " -o " + temp("sewn.ply"));
  ASSERT_EQ(sewn.exit_code, 0) << sewn.err;
  EXPECT_NE(sewn.out.find("Repaired: 7 vertices at one position joined"), std::string::npos)
      << sewn.out;
  EXPECT_NE(sewn.out.find("genus-0 surface with 2 boundary loops"), std::string::npos) << sewn.out;
  const CliRun cut = ricci_flow(temp("cut-cylinder.off") + " --keep-cuts -o " + temp("cut.ply"));
  ASSERT_EQ(cut.exit_code, 0) << cut.err;
  EXPECT_EQ(cut.out.find("Repaired:"), std::string::npos) << cut.out;
  EXPECT_NE(cut.out.find(": disk, " + std::to_string((around + 1) * (along + 1)) + " vertices"),
            std::string::npos)
      << cut.out;
  const ricci::test::PlyData ply = read_ply(temp("cut.ply"));
  EXPECT_EQ(ply.vertex.at("x").size(), static_cast<size_t>((around + 1) * (along + 1)));
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

// Faces of fewer than three corners are dropped and said so (they used to go without a word).
TEST(Cli, FacesOfFewerThanThreeCornersAreReported) {
  const std::string mesh = temp("short-faces.obj"), report = temp("short-faces.json");
  write_file(mesh, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\nf 3\n");
  const CliRun r = ricci_flow(mesh + " -o " + temp("short-faces.ply") + " --report " + report);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("2 faces with fewer than three corners dropped"), std::string::npos)
      << r.out;
  EXPECT_NE(slurp(report).find("\"what\": \"faces with fewer than three corners dropped\", "
                               "\"element\": \"face\", \"count\": 2"),
            std::string::npos)
      << slurp(report);
  const CliRun strict = ricci_flow(mesh + " -o " + temp("short-faces.ply") + " --strict");
  EXPECT_EQ(strict.exit_code, 1);
  EXPECT_NE(strict.err.find("2 faces with fewer than three corners"), std::string::npos)
      << strict.err;
}

}  // namespace
