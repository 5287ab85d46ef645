// The plugin's computation and result writing on MeshLab's own mesh type (CMeshO), without a
// GUI: attributes, UVs and quality are written on success, and nothing at all on failure.
#include "filter_computation.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include <common/ml_mesh_type.h>
#include <gtest/gtest.h>
#include <vcg/complex/append.h>
#include <wrap/io_trimesh/import.h>

#include "ricci/mesh/errors.h"
#include "ricci/report/report.h"
#include "test_meshes.h"

namespace ricci::plugin {
namespace {

void load(CMeshO& m, const std::string& name) {
  int mask = 0;
  ASSERT_EQ(vcg::tri::io::Importer<CMeshO>::Open(m, test::cgal_mesh_path(name).c_str(), mask), 0);
}

// CMeshO always has quality and color; texture coordinates are optional.
void enable_outputs(CMeshO& m) {
  m.vert.EnableTexCoord();
  m.face.EnableWedgeTexCoord();
}

// vcglib's mesh destructor leaves custom attributes allocated (MeshLab frees them itself).
struct FreeAttributesAtExit {
  CMeshO& m;
  ~FreeAttributesAtExit() { m.ClearAttributes(); }
};

bool has_attribute(CMeshO& m, const char* name) {
  return vcg::tri::HasPerVertexAttribute(m, name);
}

TEST(PluginComputation, RepairedMeshIsRebuiltWithItsResults) {
  // Face 0 repeats a vertex (dropped), faces 1 and 2 share only vertex 0 (split): the mesh is
  // rebuilt with 6 vertices and 2 faces, each triangle a chart of its own.
  const std::string path = ::testing::TempDir() + "/ricci_plugin_dirty.off";
  std::ofstream(path) << "OFF\n5 3 0\n0 0 0\n1 0 0\n1 1 0\n-1 0 0\n-1 -1 0\n"
                         "3 0 0 1\n3 0 1 2\n3 0 3 4\n";
  CMeshO m;
  FreeAttributesAtExit cleanup{m};
  int mask = 0;
  ASSERT_EQ(vcg::tri::io::Importer<CMeshO>::Open(m, path.c_str(), mask), 0);
  ASSERT_EQ(m.fn, 3);
  const FilterSettings settings = settings_from_values({});
  const MeshInput input = read_mesh_input(m, false, settings.repair);
  const FilterComputation c = compute(input, settings);
  EXPECT_TRUE(c.rebuilds(input));
  enable_outputs(m);
  write_results(m, input, settings, c);
  ASSERT_EQ(m.vert.size(), 6u);
  ASSERT_EQ(m.face.size(), 2u);
  auto u = vcg::tri::Allocator<CMeshO>::GetPerVertexAttribute<float>(m, "ricci_u");
  for (const auto& v : m.vert) EXPECT_TRUE(std::isfinite(u[v]));
  for (const auto& f : m.face) {
    const auto a = f.cV(0)->cT().P(), b = f.cV(1)->cT().P(), d = f.cV(2)->cT().P();
    EXPECT_GT((b - a) ^ (d - a), 0.0f);  // counter-clockwise in the atlas
  }
}

TEST(PluginComputation, DiskGetsAttributesUvAndQuality) {
  CMeshO m;
  FreeAttributesAtExit cleanup{m};
  load(m, "nefertiti.off");
  const FilterSettings settings = settings_from_values({});
  const MeshInput input = read_mesh_input(m, false);
  int progress_calls = 0;
  const FilterComputation c =
      compute(input, settings, [&](const FlowProgress&) { return ++progress_calls > 0; });
  ASSERT_EQ(c.uniformization().layout_kind, LayoutKind::Plane);  // auto: the unit disk
  EXPECT_GT(progress_calls, 1);
  enable_outputs(m);
  write_results(m, input, settings, c);
  for (const char* name :
       {"ricci_u", "ricci_radius", "ricci_curvature", "ricci_target", "ricci_layout"}) {
    EXPECT_TRUE(has_attribute(m, name)) << name;
  }
  auto u = vcg::tri::Allocator<CMeshO>::GetPerVertexAttribute<float>(m, "ricci_u");
  auto k = vcg::tri::Allocator<CMeshO>::GetPerVertexAttribute<float>(m, "ricci_curvature");
  auto target = vcg::tri::Allocator<CMeshO>::GetPerVertexAttribute<float>(m, "ricci_target");
  auto layout = vcg::tri::Allocator<CMeshO>::GetPerVertexAttribute<vcg::Point3f>(m, "ricci_layout");
  const CompactMesh& mesh = input.mesh();
  bool colors_differ = false;
  for (size_t i = 0; i < m.vert.size(); ++i) {
    const auto& v = m.vert[i];
    EXPECT_FLOAT_EQ(v.cQ(), u[v]);
    EXPECT_FLOAT_EQ(u[v], static_cast<float>(c.result().u[input.compact_index[i]]));
    EXPECT_FALSE(std::isnan(target[v]));
    EXPECT_NEAR(k[v], target[v], 1e-6f);
    if (mesh.is_boundary_vertex(input.compact_index[i])) {
      EXPECT_NEAR(layout[v].Norm(), 1.0f, 1e-5f);  // on the unit circle
    } else {
      EXPECT_NEAR(k[v], 0.0f, 1e-6f);
      EXPECT_LT(layout[v].Norm(), 1.0f);
    }
    EXPECT_GE(v.cT().U(), 0.0f);
    EXPECT_LE(v.cT().U(), 1.0f);
    EXPECT_GE(v.cT().V(), 0.0f);
    EXPECT_LE(v.cT().V(), 1.0f);
    EXPECT_EQ(layout[v].Z(), 0.0f);
    colors_differ = colors_differ || !(v.cC() == m.vert[0].cC());
  }
  EXPECT_TRUE(colors_differ) << "quality color ramp";
  const auto lines = summary_lines(input.mesh(), c.uniformization(), {});
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_NE(lines[1].find("Converged in"), std::string::npos);
  EXPECT_NE(lines[2].find("on circles"), std::string::npos);
  EXPECT_NE(lines[3].find("Layout (plane): 0 of the input's faces flipped"), std::string::npos)
      << lines[3];

  // The optional layout layer: a copy of the mesh moved onto the plane; its edges that the flow
  // kept (not flipped) have their flat lengths, all scaled by the same factor (unit disk).
  const Triangulation& flow_triangulation = result_triangulation(mesh, c.result());
  std::map<std::pair<int, int>, double> flat_length;
  for (int edge = 0; edge < flow_triangulation.num_edges(); ++edge) {
    const auto ends = flow_triangulation.edge_vertices(edge);
    if (ends != mesh.edge_vertices(edge)) continue;  // flipped: not an edge of the input
    flat_length[{ends[0], ends[1]}] = c.result().edge_lengths[edge];
  }
  int compared = 0;
  double scale = 0;
  CMeshO layer;
  FreeAttributesAtExit layer_cleanup{layer};
  vcg::tri::Append<CMeshO, CMeshO>::MeshCopy(layer, m);
  place_at_layout(layer, c);
  for (const auto& f : layer.face) {
    for (int e = 0; e < 3; ++e) {
      EXPECT_EQ(f.cP(e).Z(), 0.0f);
      const int a = input.compact_index[vcg::tri::Index(layer, f.cV(e))];
      const int b = input.compact_index[vcg::tri::Index(layer, f.cV((e + 1) % 3))];
      const auto it = flat_length.find({std::min(a, b), std::max(a, b)});
      if (it == flat_length.end()) continue;
      const double ratio = vcg::Distance(f.cP(e), f.cP((e + 1) % 3)) / it->second;
      if (scale == 0) scale = ratio;
      EXPECT_NEAR(ratio / scale, 1.0, 1e-5);
      ++compared;
    }
  }
  EXPECT_GT(compared, mesh.num_edges());  // the kept edges, interior ones from both sides
}

TEST(PluginComputation, CenterAndAxisVerticesNormalizeTheDisk) {
  CMeshO m;
  FreeAttributesAtExit cleanup{m};
  load(m, "nefertiti.off");
  const MeshInput input = read_mesh_input(m, false);
  int center = 0;
  while (input.mesh().is_boundary_vertex(input.compact_index[center])) ++center;
  const int axis = input.mesh().boundary_loops()[0][0];  // compact = slot: nothing is deleted
  const FilterComputation c =
      compute(input, settings_from_values({{"centerVertex", center}, {"axisVertex", axis}}));
  const auto& p = c.uniformization().position;
  EXPECT_LE(p[input.compact_index[center]].norm(), 1e-12);
  EXPECT_NEAR(p[axis].x(), 1.0, 1e-8);
  EXPECT_NEAR(p[axis].y(), 0.0, 1e-12);
  try {
    compute(input, settings_from_values({{"centerVertex", 100000}}));
    ADD_FAILURE() << "an out-of-range center vertex was accepted";
  } catch (const ricci::Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a vertex of the mesh"), std::string::npos);
  }
}

TEST(PluginComputation, ClosedSurfacesGetTheirLayouts) {
  for (const char* name : {"sphere.off", "eight.off", "pipe.off"}) {
    CMeshO m;
    FreeAttributesAtExit cleanup{m};
    load(m, name);
    const FilterSettings settings = settings_from_values({{"scheme", 2}});
    const MeshInput input = read_mesh_input(m, false);
    const FilterComputation c = compute(input, settings);
    enable_outputs(m);
    write_results(m, input, settings, c);
    EXPECT_TRUE(has_attribute(m, "ricci_u"));
    const WrittenComponents written = written_components(settings, c);
    EXPECT_FALSE(written.vertex_texcoord);
    if (std::string(name) == "sphere.off") {
      // On the unit sphere: a per-vertex layout, no texture.
      EXPECT_FALSE(written.wedge_texcoord);
      ASSERT_TRUE(has_attribute(m, "ricci_layout"));
      auto layout =
          vcg::tri::Allocator<CMeshO>::GetPerVertexAttribute<vcg::Point3f>(m, "ricci_layout");
      for (const auto& v : m.vert) EXPECT_NEAR(layout[v].Norm(), 1.0f, 1e-6f);
    } else {
      // Cut open: wedge texture coordinates in the unit square.
      EXPECT_TRUE(written.wedge_texcoord);
      EXPECT_FALSE(has_attribute(m, "ricci_layout"));
      for (const auto& f : m.face) {
        for (int k = 0; k < 3; ++k) {
          EXPECT_GE(f.cWT(k).U(), 0.0f);
          EXPECT_LE(f.cWT(k).V(), 1.0f);
        }
      }
      const auto lines = summary_lines(input.mesh(), c.uniformization(), {});
      EXPECT_TRUE(std::any_of(lines.begin(), lines.end(), [](const std::string& l) {
        return l.find("relation error") != std::string::npos;
      })) << lines.back();
    }
  }
}

TEST(PluginComputation, MixedEpsFromSelectionAndTargetFromQuality) {
  CMeshO m;
  load(m, "nefertiti.off");
  for (size_t i = 0; i < m.vert.size(); ++i) {
    if (i % 2 == 0) m.vert[i].SetS();
  }
  const MeshInput free_input = read_mesh_input(m, false);
  // Quality = the free-boundary target: 0 inside, NaN (u fixed) on the boundary.
  for (size_t i = 0; i < m.vert.size(); ++i) {
    m.vert[i].Q() = free_input.mesh().is_boundary_vertex(free_input.compact_index[i]) ? NAN : 0.0f;
  }
  const MeshInput input = read_mesh_input(m, true);
  const FilterComputation by_quality =
      compute(input, settings_from_values({{"scheme", 5}, {"target", 3}}));
  const FilterComputation by_preset =
      compute(input, settings_from_values({{"scheme", 5}, {"target", 1}}));
  EXPECT_LE((by_quality.result().u - by_preset.result().u).cwiseAbs().maxCoeff(), 1e-12);
  // The selection really made the scheme mixed: the result differs from plain Yamabe.
  const FilterComputation yamabe =
      compute(input, settings_from_values({{"scheme", 3}, {"target", 1}}));
  EXPECT_GT((yamabe.result().radius - by_preset.result().radius).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(PluginComputation, FailureLeavesTheMeshUntouched) {
  struct Case {
    const char* mesh;
    ParameterValues values;
    const char* reason;
  };
  const Case cases[] = {
      {"blobby_3cc.off", {{"strictMesh", 1}}, "connected components"},
      {"pipe.off", {{"geometry", 3}}, "spherical geometry needs"},
      {"elk.off", {{"scheme", 3}, {"edgeFlips", 0}}, "stalled"},
      {"nefertiti.off", {{"target", 3}}, "no vertex quality"},
      {"sphere.off", {{"target", 1}}, "needs a boundary"},
  };
  for (const auto& c : cases) {
    CMeshO m;
    load(m, c.mesh);
    for (auto& v : m.vert) v.Q() = 0.5f;  // data that must survive
    std::vector<vcg::Point3f> before;
    std::vector<vcg::Color4b> colors_before;
    for (const auto& v : m.vert) {
      before.push_back(v.cP());
      colors_before.push_back(v.cC());
    }
    try {
      const FilterSettings settings = settings_from_values(c.values);
      const MeshInput input = read_mesh_input(m, false, settings.repair);
      compute(input, settings);
      ADD_FAILURE() << c.mesh << ": expected an error";
    } catch (const ricci::Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.reason), std::string::npos) << e.what();
    }
    EXPECT_FALSE(has_attribute(m, "ricci_u"));
    EXPECT_FALSE(m.vert.IsTexCoordEnabled());
    EXPECT_FALSE(m.face.IsWedgeTexCoordEnabled());
    ASSERT_EQ(m.vert.size(), before.size());
    for (size_t i = 0; i < before.size(); ++i) {
      EXPECT_EQ(m.vert[i].cP(), before[i]);
      EXPECT_EQ(m.vert[i].cQ(), 0.5f);
      EXPECT_TRUE(m.vert[i].cC() == colors_before[i]);
    }
  }
}

}  // namespace
}  // namespace ricci::plugin
