// The plugin's parameter table, its translation into core options, and the sample .mlx scripts
// (meshlabserver aborts unless a script lists every parameter with its type).
#include "filter_settings.h"

#include <cctype>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "ricci/mesh/errors.h"

namespace ricci::plugin {
namespace {

TEST(PluginSettings, DefaultsAreTheCoreDefaults) {
  const FilterSettings s = settings_from_values({});
  EXPECT_EQ(s.geometry, GeometryChoice::Auto);
  EXPECT_EQ(s.scheme, Scheme::Yamabe);
  EXPECT_EQ(s.target, TargetChoice::Auto);
  EXPECT_DOUBLE_EQ(s.tolerance, FlowOptions{}.tolerance);
  EXPECT_EQ(s.max_iterations, FlowOptions{}.max_iterations);
  EXPECT_EQ(s.max_step_halvings, FlowOptions{}.max_step_halvings);
  EXPECT_EQ(s.linear_solver, LinearSolverKind::Cholmod);
  EXPECT_TRUE(s.write_texture_coordinates);
  EXPECT_TRUE(s.write_quality);
  EXPECT_FALSE(s.add_layout_layer);
  EXPECT_EQ(s.center_vertex, -1);
  EXPECT_EQ(s.axis_vertex, -1);
  // Edge flips when needed, as the core's default.
  EXPECT_TRUE(s.edge_flips);
  EXPECT_FALSE(s.always_flip);
  EXPECT_TRUE(settings_from_values({{"alwaysFlip", 1}}).always_flip);
}

TEST(PluginSettings, EveryEnumChoiceTranslates) {
  const Scheme schemes[] = {Scheme::Tangential, Scheme::Thurston,      Scheme::InversiveDistance,
                            Scheme::Yamabe,     Scheme::VirtualRadius, Scheme::Mixed};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(settings_from_values({{"scheme", i}}).scheme, schemes[i]);
  EXPECT_EQ(settings_from_values({{"geometry", 2}}).geometry, GeometryChoice::Hyperbolic);
  EXPECT_EQ(settings_from_values({{"target", 3}}).target, TargetChoice::VertexQuality);
  EXPECT_EQ(settings_from_values({{"mixedEps", 1}}).mixed_eps, MixedEpsSource::QualitySign);
  EXPECT_EQ(settings_from_values({{"linearSolver", 1}}).linear_solver, LinearSolverKind::Ldlt);
  const FilterSettings s = settings_from_values({{"thurstonAngle", 45},
                                                 {"tolerance", 1e-8},
                                                 {"maxIterations", 7},
                                                 {"writeUV", 0},
                                                 {"layoutLayer", 1}});
  EXPECT_EQ(s.thurston_angle_degrees, 45);
  EXPECT_EQ(s.tolerance, 1e-8);
  EXPECT_EQ(s.max_iterations, 7);
  EXPECT_FALSE(s.write_texture_coordinates);
  EXPECT_TRUE(s.add_layout_layer);
}

TEST(PluginSettings, OutOfRangeValuesAreRefused) {
  EXPECT_THROW(settings_from_values({{"scheme", 6}}), InvalidArgumentError);
  EXPECT_THROW(settings_from_values({{"geometry", -1}}), InvalidArgumentError);
  EXPECT_THROW(settings_from_values({{"tolerance", 0}}), InvalidArgumentError);
  EXPECT_THROW(settings_from_values({{"maxIterations", -3}}), InvalidArgumentError);
  EXPECT_THROW(settings_from_values({{"noSuchParameter", 1}}), InvalidArgumentError);
  EXPECT_THROW(settings_from_values({{"centerVertex", -2}}), InvalidArgumentError);
  EXPECT_THROW(settings_from_values({{"axisVertex", 1.5}}), InvalidArgumentError);
}

TEST(PluginSettings, PythonNamesAreDistinctSnakeCase) {
  EXPECT_EQ(python_parameter_name("thurstonAngle"), "thurston_angle");
  EXPECT_EQ(python_parameter_name("writeUV"), "write_uv");
  EXPECT_EQ(python_parameter_name("geometry"), "geometry");
  std::set<std::string> names;
  for (const ParameterSpec& spec : parameter_specs()) {
    const std::string name = python_parameter_name(spec.name);
    EXPECT_TRUE(names.insert(name).second) << name;
    for (char c : name)
      EXPECT_TRUE(std::islower(static_cast<unsigned char>(c)) || c == '_') << name;
  }
  EXPECT_EQ(python_filter_name(), "compute_texcoord_parametrization_ricci_flow");
}

TEST(PluginSettings, EveryParameterHasLabelAndTooltip) {
  std::set<std::string> names;
  for (const auto& spec : parameter_specs()) {
    EXPECT_TRUE(names.insert(spec.name).second) << "duplicate " << spec.name;
    EXPECT_FALSE(spec.description.empty()) << spec.name;
    EXPECT_GT(spec.tooltip.size(), 20u) << spec.name;
    if (spec.kind == ParameterSpec::Kind::Enum) {
      EXPECT_LT(spec.default_value, spec.enum_labels.size()) << spec.name;
    }
  }
  EXPECT_NE(filter_info().find("Unified Surface Ricci Flow"), std::string::npos);
}

const char* type_name(ParameterSpec::Kind k) {
  switch (k) {
    case ParameterSpec::Kind::Enum:
      return "RichEnum";
    case ParameterSpec::Kind::Float:
      return "RichFloat";
    case ParameterSpec::Kind::Int:
      return "RichInt";
    case ParameterSpec::Kind::Bool:
      return "RichBool";
  }
  return "";
}

class SampleScript : public ::testing::TestWithParam<std::string> {};

TEST_P(SampleScript, ListsEveryParameterWithItsTypeAndLabels) {
  std::ifstream in(std::string(RICCI_SOURCE_DIR) + "/plugin/scripts/" + GetParam());
  ASSERT_TRUE(in.good()) << GetParam();
  std::stringstream text;
  text << in.rdbuf();
  const std::string xml = text.str();
  EXPECT_NE(xml.find("<filter name=\"" + filter_name() + "\">"), std::string::npos);
  const std::regex param_re("<Param ([^>]*)/>");
  const std::regex attr_re("(\\w+)=\"([^\"]*)\"");
  std::map<std::string, std::map<std::string, std::string>> params;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), param_re);
       it != std::sregex_iterator(); ++it) {
    std::map<std::string, std::string> attrs;
    const std::string body = (*it)[1];
    for (auto a = std::sregex_iterator(body.begin(), body.end(), attr_re);
         a != std::sregex_iterator(); ++a) {
      attrs[(*a)[1]] = (*a)[2];
    }
    params[attrs["name"]] = attrs;
  }
  EXPECT_EQ(params.size(), parameter_specs().size());
  ParameterValues values;
  for (const auto& spec : parameter_specs()) {
    ASSERT_TRUE(params.count(spec.name)) << GetParam() << " lacks " << spec.name;
    const auto& attrs = params[spec.name];
    EXPECT_EQ(attrs.at("type"), type_name(spec.kind)) << spec.name;
    if (spec.kind == ParameterSpec::Kind::Enum) {
      EXPECT_EQ(attrs.at("enum_cardinality"), std::to_string(spec.enum_labels.size()));
      for (size_t i = 0; i < spec.enum_labels.size(); ++i) {
        EXPECT_EQ(attrs.at("enum_val" + std::to_string(i)), spec.enum_labels[i]) << spec.name;
      }
    }
    const std::string v = attrs.at("value");
    values[spec.name] = v == "true" ? 1 : v == "false" ? 0 : std::stod(v);
  }
  EXPECT_NO_THROW(settings_from_values(values));
}

INSTANTIATE_TEST_SUITE_P(Plugin, SampleScript,
                         ::testing::Values("ricci_flow_auto.mlx", "ricci_flow_euclidean.mlx",
                                           "ricci_flow_hyperbolic.mlx", "ricci_flow_spherical.mlx",
                                           "ricci_flow_atlas.mlx"),
                         [](const auto& p) {
                           std::string n = p.param;
                           return n.substr(0, n.find('.'));
                         });

}  // namespace
}  // namespace ricci::plugin
