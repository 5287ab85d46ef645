// The plugin inside the real meshlabserver (Debian's MeshLab 2020.09, under xvfb-run, from a
// private prefix): every sample script on real meshes of each topology, and bad meshes.
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "ply_reader.h"
#include "ricci/mesh/geometry.h"
#include "test_meshes.h"

using ricci::kPi;

namespace {

struct ServerRun {
  int exit_code = -1;
  std::string log;
};

std::string temp(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return ::testing::TempDir() + "/ricci_meshlab_" + info->name() + "_" + name;
}

std::string script(const std::string& name) {
  return std::string(RICCI_SOURCE_DIR) + "/plugin/scripts/" + name;
}

// `mask`: more of meshlabserver's -m components to write (e.g. "vf", the vertex flags).
ServerRun meshlabserver(const std::string& input, const std::string& output, const std::string& mlx,
                        const std::string& mask = "") {
  const std::string log = temp("server.log");
  std::remove(output.c_str());
  const std::string cmd = "xvfb-run -a " + std::string(RICCI_MESHLAB_PREFIX) +
                          "/bin/meshlabserver -i " + input + " -o " + output + " -m vq vt wt " +
                          mask + " -s " + mlx + " >" + log + " 2>&1 </dev/null";
  const int status = std::system(cmd.c_str());
  ServerRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(log);
  std::stringstream s;
  s << in.rdbuf();
  r.log = s.str();
  return r;
}

bool exists(const std::string& path) {
  return std::ifstream(path).good();
}

TEST(MeshlabServer, EuclideanScriptFlattensADisk) {
  const std::string out = temp("disk.ply");
  const ServerRun r = meshlabserver(ricci::test::cgal_mesh_path("nefertiti.off"), out,
                                    script("ricci_flow_euclidean.mlx"));
  ASSERT_EQ(r.exit_code, 0) << r.log;
  EXPECT_NE(r.log.find("Converged in"), std::string::npos) << r.log;
  const ricci::test::PlyData ply = ricci::test::read_ply(out);
  ASSERT_TRUE(ply.has_vertex("quality") && ply.has_vertex("texture_u") &&
              ply.has_vertex("texture_v"));
  const ricci::CompactMesh mesh = ricci::test::cgal_mesh("nefertiti.off");
  ASSERT_EQ(ply.vertex.at("quality").size(), static_cast<size_t>(mesh.num_vertices()));
  double max_u = 0;
  // The auto target maps a disk onto the unit disk: the boundary's UVs lie on one circle
  // (algebraic least-squares fit x^2 + y^2 + d x + e y + f = 0).
  const std::vector<int>& loop = mesh.boundary_loops()[0];
  Eigen::MatrixXd fit(loop.size(), 3);
  Eigen::VectorXd rhs(loop.size());
  for (size_t i = 0; i < loop.size(); ++i) {
    const double x = ply.vertex.at("texture_u")[loop[i]], y = ply.vertex.at("texture_v")[loop[i]];
    fit.row(static_cast<long>(i)) << x, y, 1.0;
    rhs[static_cast<long>(i)] = -(x * x + y * y);
  }
  const Eigen::Vector3d def = fit.colPivHouseholderQr().solve(rhs);
  const Eigen::Vector2d center(-def[0] / 2, -def[1] / 2);
  const double radius = std::sqrt(center.squaredNorm() - def[2]);
  for (int v : loop) {
    const Eigen::Vector2d uv(ply.vertex.at("texture_u")[v], ply.vertex.at("texture_v")[v]);
    EXPECT_NEAR((uv - center).norm() / radius, 1.0, 1e-5) << "boundary UV off the circle";
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double u = ply.vertex.at("quality")[v];
    ASSERT_TRUE(std::isfinite(u));
    max_u = std::max(max_u, std::abs(u));
    EXPECT_GE(ply.vertex.at("texture_u")[v], 0.0);
    EXPECT_LE(ply.vertex.at("texture_v")[v], 1.0);
  }
  EXPECT_GT(max_u, 0.1);
  // The UV map is the flat metric's layout, scaled: interior angle sums are 2 pi, none flipped.
  std::vector<double> angle_sum(mesh.num_vertices(), 0.0);
  const auto& tu = ply.vertex.at("texture_u");
  const auto& tv = ply.vertex.at("texture_v");
  for (const auto& t : ply.faces) {
    for (int c = 0; c < 3; ++c) {
      const int a = t[c], b = t[(c + 1) % 3], d = t[(c + 2) % 3];
      const double ux = tu[b] - tu[a], uy = tv[b] - tv[a], vx = tu[d] - tu[a], vy = tv[d] - tv[a];
      EXPECT_GT(ux * vy - uy * vx, 0.0) << "flipped UV triangle";
      angle_sum[a] += std::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
    }
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!mesh.is_boundary_vertex(v)) {
      EXPECT_NEAR(angle_sum[v], 2 * kPi, 1e-4);  // float UVs
    }
  }
}

TEST(MeshlabServer, EachGeometryScriptOnItsTopology) {
  struct Case {
    std::string mesh, mlx, geometry, layout;
  };
  const Case cases[] = {{"pipe.off", "ricci_flow_euclidean.mlx", "euclidean", "plane-cut"},
                        {"eight.off", "ricci_flow_hyperbolic.mlx", "hyperbolic", "poincare-disk"},
                        {"sphere.off", "ricci_flow_spherical.mlx", "spherical", "sphere"},
                        {"nefertiti.off", "ricci_flow_auto.mlx", "euclidean", "plane"},
                        {"head.off", "ricci_flow_auto.mlx", "euclidean", "plane"},
                        {"sphere.off", "ricci_flow_auto.mlx", "spherical", "sphere"},
                        {"pipe.off", "ricci_flow_auto.mlx", "euclidean", "plane-cut"},
                        {"eight.off", "ricci_flow_auto.mlx", "hyperbolic", "poincare-disk"}};
  for (const auto& c : cases) {
    const std::string out = temp("closed.ply");
    const ServerRun r = meshlabserver(ricci::test::cgal_mesh_path(c.mesh), out, script(c.mlx));
    ASSERT_EQ(r.exit_code, 0) << c.mesh << " " << c.mlx << "\n" << r.log;
    EXPECT_NE(r.log.find(c.geometry + " geometry"), std::string::npos) << r.log;
    const ricci::test::PlyData ply = ricci::test::read_ply(out);
    ASSERT_TRUE(ply.has_vertex("quality")) << c.mesh;
    double lo = INFINITY, hi = -INFINITY;
    for (double u : ply.vertex.at("quality")) {
      ASSERT_TRUE(std::isfinite(u));
      lo = std::min(lo, u);
      hi = std::max(hi, u);
    }
    EXPECT_GT(hi - lo, 1e-3) << c.mesh << ": quality holds u, which varies";
    EXPECT_NE(r.log.find("Layout (" + c.layout + ")"), std::string::npos) << r.log;
    // Surfaces cut open come back with wedge texture coordinates, the others per vertex.
    const bool cut_open = c.layout == "plane-cut" || c.layout == "poincare-disk";
    if (cut_open) {
      EXPECT_EQ(ply.face_texcoords.size(), ply.faces.size()) << c.mesh;
    }
    EXPECT_EQ(ply.has_vertex("texture_u"), c.layout == "plane") << c.mesh;
    for (const auto& t : ply.face_texcoords) {
      for (double x : t) {
        EXPECT_GE(x, 0.0);
        EXPECT_LE(x, 1.0);
      }
    }
  }
}

TEST(MeshlabServer, AtlasScriptGivesAClosedMeshPackedWedgeTextureCoordinates) {
  // A closed genus-2 surface, which the other targets lay out in the Poincare disk: the atlas
  // gives charts in the plane, packed, their faces counter-clockwise, the cones selected.
  const std::string out = temp("atlas.ply");
  const ServerRun r = meshlabserver(ricci::test::cgal_mesh_path("eight.off"), out,
                                    script("ricci_flow_atlas.mlx"), "vf");
  ASSERT_EQ(r.exit_code, 0) << r.log;
  EXPECT_NE(r.log.find("Layout (atlas)"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("Atlas: "), std::string::npos) << r.log;
  const ricci::test::PlyData ply = ricci::test::read_ply(out);
  ASSERT_EQ(ply.face_texcoords.size(), ply.faces.size());
  for (const auto& t : ply.face_texcoords) {
    for (double x : t) {
      EXPECT_GE(x, 0.0);
      EXPECT_LE(x, 1.0);
    }
    EXPECT_GT((t[2] - t[0]) * (t[5] - t[1]) - (t[3] - t[1]) * (t[4] - t[0]), 0);
  }
  ASSERT_TRUE(ply.has_vertex("flags"));
  int selected = 0;
  for (double f : ply.vertex.at("flags")) selected += (static_cast<int>(f) & 0x20) != 0;
  EXPECT_GT(selected, 0) << "the cones are selected";
}

TEST(MeshlabServer, DirtyMeshIsRepairedAndMapped) {
  // A bowtie (two triangles sharing a vertex) and a duplicate face: by default the vertex is split,
  // the duplicate dropped, each triangle mapped onto its own chart, and the log says so.
  const std::string bowtie = temp("bowtie-dup.off");
  std::ofstream(bowtie) << "OFF\n5 3 0\n0 0 0\n1 0 0\n1 1 0\n-1 0 0\n-1 -1 0\n3 0 1 2\n3 0 3 4\n"
                           "3 0 1 2\n";
  const std::string out = temp("bowtie-repaired.ply");
  const ServerRun r = meshlabserver(bowtie, out, script("ricci_flow_auto.mlx"));
  ASSERT_EQ(r.exit_code, 0) << r.log;
  EXPECT_NE(r.log.find("Repaired: 1 non-manifold vertices split"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("Repaired: 1 duplicate faces dropped"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("2 connected components"), std::string::npos) << r.log;
  const ricci::test::PlyData ply = ricci::test::read_ply(out);
  ASSERT_EQ(ply.faces.size(), 2u);
  EXPECT_EQ(ply.vertex.at("x").size(), 6u);  // vertex 0 copied for the second triangle
  ASSERT_TRUE(ply.has_vertex("texture_u"));
  for (const auto& f : ply.faces) {  // both charts counter-clockwise in the atlas
    const auto& u = ply.vertex.at("texture_u");
    const auto& v = ply.vertex.at("texture_v");
    EXPECT_GT((u[f[1]] - u[f[0]]) * (v[f[2]] - v[f[0]]) - (v[f[1]] - v[f[0]]) * (u[f[2]] - u[f[0]]),
              0);
  }
}

TEST(MeshlabServer, FlipsThatTurnInputFacesGiveTheCommonSubdivision) {
  // elk.off (a torus scan) needs edge flips, and some of its faces drawn by their corners would
  // turn over: the mesh written is the input cut along the flipped triangulation, its vertices
  // first, with wedge texture coordinates that turn no face over.
  const ricci::CompactMesh mesh = ricci::test::cgal_mesh("elk.off");
  const std::string out = temp("elk.ply");
  const ServerRun r =
      meshlabserver(ricci::test::cgal_mesh_path("elk.off"), out, script("ricci_flow_auto.mlx"));
  ASSERT_EQ(r.exit_code, 0) << r.log;
  EXPECT_NE(r.log.find("Common subdivision: "), std::string::npos) << r.log;
  const ricci::test::PlyData ply = ricci::test::read_ply(out);
  const auto &x = ply.vertex.at("x"), &y = ply.vertex.at("y"), &z = ply.vertex.at("z");
  ASSERT_GT(x.size(), static_cast<size_t>(mesh.num_vertices()));
  for (int v = 0; v < mesh.num_vertices(); ++v) {  // MeshLab keeps positions in float
    const Eigen::Vector3d p(x[v], y[v], z[v]);
    ASSERT_LE((p - mesh.positions()[v]).norm(), 1e-6 * (1 + mesh.positions()[v].norm())) << v;
  }
  ASSERT_EQ(ply.face_texcoords.size(), ply.faces.size());
  int turned = 0;
  for (const auto& t : ply.face_texcoords) {
    turned += !((t[2] - t[0]) * (t[5] - t[1]) - (t[3] - t[1]) * (t[4] - t[0]) > 0);
  }
  EXPECT_EQ(turned, 0);
}

TEST(MeshlabServer, BadMeshFailsWithTheReasonAndNoOutput) {
  const std::string bowtie = temp("bowtie.off");
  std::ofstream(bowtie) << "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n-1 0 0\n-1 -1 0\n3 0 1 2\n3 0 3 4\n";
  const std::string out = temp("never.ply");
  // With 'Refuse meshes that need repairs' on, the bowtie is refused.
  std::ifstream in(script("ricci_flow_auto.mlx"));
  std::stringstream text;
  text << in.rdbuf();
  std::string strict = text.str();
  const std::string off = "name=\"strictMesh\" value=\"false\"";
  ASSERT_NE(strict.find(off), std::string::npos);
  strict.replace(strict.find(off), off.size(), "name=\"strictMesh\" value=\"true\"");
  const std::string strict_script = temp("strict.mlx");
  std::ofstream(strict_script) << strict;
  ServerRun r = meshlabserver(bowtie, out, strict_script);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.log.find("Ricci flow failed, the mesh is unchanged: mesh: 1 non-manifold vertices"),
            std::string::npos)
      << r.log;
  EXPECT_FALSE(exists(out));
  r = meshlabserver(ricci::test::cgal_mesh_path("pipe.off"), out,
                    script("ricci_flow_spherical.mlx"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.log.find("spherical geometry needs sum Kbar < 2 pi chi"), std::string::npos) << r.log;
  EXPECT_FALSE(exists(out));
}

}  // namespace
