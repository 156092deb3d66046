// The parameter schema is the one declaration of every config parameter: the loader reads exactly
// its keys with its rules, its defaults obey its rules, every parameter of the equations reaches
// the generated equations, and the table of doc/reference/parameters.md is what the schema prints.
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "kane_sim/config/load_config.h"
#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/model/generated_mechanism.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

YAML::Node shippedYaml() { return YAML::LoadFile(test::configPath("mechanism.yaml")); }

// The YAML spelling of a value for a parameter of `spec`'s kind.
YAML::Node yamlValue(const std::string& text) { return YAML::Load(text); }

TEST(ParameterSchema, PathsAndReconfigureNamesAreUnique) {
  std::set<std::string> paths, names;
  for (const ParameterSpec& p : parameterSchema()) {
    EXPECT_TRUE(paths.insert(p.path()).second) << p.path();
    if (p.reconfigurable()) {
      EXPECT_TRUE(names.insert(p.reconfigure.name).second) << p.path();
    }
    EXPECT_NE(std::string(p.doc), "") << p.path();
    bool in_a_section = false;
    for (const SectionSpec& s : configSections()) in_a_section |= p.section == std::string(s.name);
    EXPECT_TRUE(in_a_section) << p.path();
  }
  // Each name leads back to its row; a reconfigurable row of the equations (or the drive's) has
  // its energy booked and no other has; every resistance and its law's shape is reconfigurable.
  for (const std::string& name : names) EXPECT_NE(findReconfigurable(name), nullptr) << name;
  int physical = 0;
  for (const ParameterSpec& p : parameterSchema()) {
    const bool booked = inEquations(p.role) || p.role == ParameterRole::kDrive;
    if (p.reconfigurable()) {
      EXPECT_EQ(p.reconfigure.level, booked ? 1 : 0) << p.path();
    }
    if (p.role != ParameterRole::kDissipative && p.role != ParameterRole::kLoadShape) continue;
    ++physical;
    EXPECT_TRUE(p.reconfigurable()) << p.path();
  }
  EXPECT_GT(physical, 0);
}

// The shipped config holds every key of the schema it sets and no other: a file written from the
// schema loads with no warning, and every key of the shipped file is in the schema.
TEST(ParameterSchema, TheShippedConfigUsesOnlySchemaKeys) {
  const YAML::Node root = shippedYaml();
  for (const auto& section : root)
    for (const auto& entry : section.second)
      EXPECT_NE(findParameter(section.first.Scalar(), entry.first.Scalar()), nullptr)
          << section.first.Scalar() << "." << entry.first.Scalar();
}

// Each optional parameter's default (the Config initializer) obeys its own rule: written out
// explicitly, it loads to the same config as leaving the key out.
TEST(ParameterSchema, DefaultsObeyTheirRulesAndReadBackUnchanged) {
  const Config base = loadConfig(shippedYaml()).config;
  const Config defaults;
  for (const ParameterSpec& p : parameterSchema()) {
    if (p.required || *p.default_text) continue;
    YAML::Node root = YAML::Clone(shippedYaml());
    root[p.section][p.key] = yamlValue(valueText(p, defaults));
    Config loaded;
    ASSERT_NO_THROW(loaded = loadConfig(root).config)
        << p.path() << " = " << valueText(p, defaults);
    EXPECT_EQ(valueText(p, loaded), valueText(p, base)) << p.path();
  }
}

// Every value a parameter can hold goes through the loader into the field the schema names:
// written as a different valid value, numericValue/valueText read it back from the config.
TEST(ParameterSchema, EachKeyReachesTheFieldItNames) {
  for (const ParameterSpec& p : parameterSchema()) {
    YAML::Node root = YAML::Clone(shippedYaml());
    std::string text;
    if (p.field.flag) {
      text = valueText(p, Config{}) == "true" ? "false" : "true";
    } else if (p.field.get_choice) {
      text = p.choices.back();
    } else if (p.field.text) {
      text = p.key == std::string("prefix") ? "robot_a" : "map";
    } else {
      continue;
    }
    root[p.section][p.key] = text;
    const Config loaded = loadConfig(root).config;
    EXPECT_EQ(valueText(p, loaded), text) << p.path();
  }
  // Numbers: scale each by a factor its rule allows and the mechanism survives.
  for (const ParameterSpec& p : parameterSchema()) {
    if (!(p.field.number || p.field.whole)) continue;
    if (p.path() == "simulation.publish_rate" || p.path() == "simulation.physics_rate") continue;
    YAML::Node root = YAML::Clone(shippedYaml());
    const Config base = loadConfig(root).config;
    double value = numericValue(p, base);
    value = value == 0.0 ? 1.0 : value * (p.rule.kind == ValueRule::kRange ? 0.5 : 1.25);
    if (p.field.whole) value = std::floor(value) + 1.0;
    if (p.section == std::string("initial_state")) value = numericValue(p, base) + 0.01;
    root[p.section][p.key] = value;
    Config loaded;
    ASSERT_NO_THROW(loaded = loadConfig(root).config) << p.path() << " = " << value;
    EXPECT_EQ(numericValue(p, loaded), value) << p.path();
  }
}

// Hostile values of every number: each is refused naming the key, or (finite rules) accepted;
// never a crash, never a silent change.
TEST(ParameterSchema, HostileNumbersAreRefusedNamingTheKey) {
  for (const ParameterSpec& p : parameterSchema()) {
    if (!(p.field.number || p.field.whole)) continue;
    for (const char* hostile : {".nan", ".inf", "-.inf", "1e309", "twelve", "[1, 2]", ""}) {
      YAML::Node root = YAML::Clone(shippedYaml());
      root[p.section][p.key] = YAML::Load(hostile);
      if (std::string(hostile).empty() && !p.required) root[p.section][p.key] = YAML::Node();
      try {
        loadConfig(root);
        ADD_FAILURE() << p.path() << " = '" << hostile << "' accepted";
      } catch (const ConfigError& e) {
        EXPECT_EQ(e.key(), p.path()) << e.what();
      }
    }
  }
}

TEST(ParameterSchema, EveryParameterOfTheEquationsReachesTheGeneratedOnes) {
  // A distinct value per mechanism and damping parameter must appear among the generated
  // equations' constants: a parameter the schema declares but constantsOf forgets fails here.
  const Config base = test::defaultConfig();
  const generated::Constants reference = GeneratedMechanism(mechanismModel(base)).constants();
  static_assert(sizeof(generated::Constants) % sizeof(double) == 0, "Constants holds doubles");
  constexpr std::size_t kCount = sizeof(generated::Constants) / sizeof(double);
  for (const ParameterSpec& p : parameterSchema()) {
    if (!inEquations(p.role)) continue;
    Config config = base;
    const double marker = numericValue(p, base) + 0.123456789;
    p.field.number(config) = marker;
    const generated::Constants c = GeneratedMechanism(mechanismModel(config)).constants();
    const double* values = reinterpret_cast<const double*>(&c);
    const double* before = reinterpret_cast<const double*>(&reference);
    bool found = false;
    for (std::size_t i = 0; i < kCount; ++i) found |= values[i] == marker && before[i] != marker;
    EXPECT_TRUE(found) << p.path() << " does not reach generated::Constants";
  }
}

TEST(ParameterSchema, TheDocumentedTableIsTheSchemas) {
  EXPECT_EQ(test::generatedDocSection("doc/reference/parameters.md",
                                      "rosrun kane_sim config_info parameters"),
            parameterTable())
      << "regenerate the table of doc/reference/parameters.md: rosrun kane_sim config_info "
         "parameters";
}

TEST(ParameterSchema, ChoicesParseByTheirSchemaNames) {
  EXPECT_EQ(parseIntegratorName("dopri5", "simulation.integrator"), IntegratorType::kDopri5);
  try {
    parseIntegratorName("euler", "x.integrator");
    ADD_FAILURE();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "config key 'x.integrator' names an unknown integrator 'euler' (valid: rk4, "
                 "dopri5)");
  }
}

}  // namespace
}  // namespace kane_sim
