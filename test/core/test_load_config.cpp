// The config loader: the shipped files, defaults, and one test per kind of bad input, each
// checking that the error names the key (and the value where there is one).
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "kane_sim/config/load_config.h"
#include "kane_sim/config/parameter_schema.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

YAML::Node defaultYaml() { return YAML::LoadFile(test::configPath("mechanism.yaml")); }

// Expects loadConfig(root) to throw a ConfigError for `key` whose message contains `text`.
void expectError(const YAML::Node& root, const std::string& key, const std::string& text) {
  try {
    loadConfig(root);
    ADD_FAILURE() << "no error for " << key;
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), key) << e.what();
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

TEST(LoadConfig, ShippedFilesLoadWithoutWarnings) {
  for (const char* file : {"mechanism.yaml", "textbook.yaml"}) {
    const LoadedConfig loaded = loadConfigFile(test::configPath(file));
    EXPECT_TRUE(loaded.warnings.empty()) << file << ": " << loaded.warnings.front();
  }
}

TEST(LoadConfig, DefaultsMatchTheTextbooksParameterSet) {
  const Config c = loadConfigFile(test::configPath("mechanism.yaml")).config;
  EXPECT_EQ(c.mechanism.rod_mass, 1.0);
  EXPECT_EQ(c.mechanism.rod_half_length, 0.25);
  EXPECT_EQ(c.mechanism.slider3_mass, 0.5);
  EXPECT_EQ(c.mechanism.slider4_mass, 0.8);
  EXPECT_EQ(c.mechanism.spring_stiffness, 200.0);
  EXPECT_EQ(c.mechanism.gravity, 9.81);
  EXPECT_DOUBLE_EQ(c.mechanism.rod_inertia, 1.0 * 0.5 * 0.5 / 12);  // m (2L)^2 / 12
  EXPECT_DOUBLE_EQ(c.initial_state.q1, M_PI / 6);
  EXPECT_DOUBLE_EQ(c.initial_state.q2, 4 * 0.25 * std::cos(M_PI / 6) + 0.3);
  EXPECT_EQ(c.simulation.physics_rate, 1000.0);
  EXPECT_EQ(c.simulation.integrator, IntegratorType::kRk4);
  const Config t = loadConfigFile(test::configPath("textbook.yaml")).config;
  EXPECT_DOUBLE_EQ(t.mechanism.rod_inertia, 1.0 * 0.25 * 0.25 / 12);  // m L^2 / 12
}

// Two files, one source of truth each: textbook.yaml is mechanism.yaml with the textbook's rod
// inertia and nothing else (the loader reads one file, so the shared values are repeated and
// this test keeps them from drifting apart).
void expectSameTree(const YAML::Node& a, const YAML::Node& b, const std::string& path) {
  ASSERT_EQ(a.Type(), b.Type()) << path;
  if (a.IsScalar()) {
    EXPECT_EQ(a.Scalar(), b.Scalar()) << path;
    return;
  }
  ASSERT_TRUE(a.IsMap()) << path;
  EXPECT_EQ(a.size(), b.size()) << path;
  for (const auto& entry : a) {
    const std::string key = entry.first.as<std::string>();
    ASSERT_TRUE(b[key]) << path << "." << key << " only in one file";
    expectSameTree(entry.second, b[key], path + "." + key);
  }
}

TEST(LoadConfig, TextbookFileDiffersFromTheDefaultOnlyInRodInertia) {
  YAML::Node physical = YAML::LoadFile(test::configPath("mechanism.yaml"));
  YAML::Node textbook = YAML::LoadFile(test::configPath("textbook.yaml"));
  ASSERT_TRUE(textbook["mechanism"]["rod_inertia"]);
  EXPECT_FALSE(physical["mechanism"]["rod_inertia"]) << "the default file uses m (2L)^2/12";
  textbook["mechanism"].remove("rod_inertia");
  expectSameTree(physical, textbook, "");
}

// The struct defaults of the optional settings are what the shipped file states: a file without
// those sections behaves exactly like config/mechanism.yaml.
TEST(LoadConfig, OptionalDefaultsEqualTheShippedFile) {
  const Config file = test::defaultConfig();
  YAML::Node root = defaultYaml();
  for (const char* section : {"simulation", "command", "frames"}) root.remove(section);
  const Config bare = loadConfig(root).config;
  const SimulationSettings &a = file.simulation, &b = bare.simulation;
  EXPECT_EQ(a.physics_rate, b.physics_rate);
  EXPECT_EQ(a.integrator, b.integrator);
  EXPECT_EQ(a.absolute_tolerance, b.absolute_tolerance);
  EXPECT_EQ(a.relative_tolerance, b.relative_tolerance);
  EXPECT_EQ(a.publish_rate, b.publish_rate);
  EXPECT_EQ(a.real_time_factor, b.real_time_factor);
  EXPECT_EQ(a.publish_clock, b.publish_clock);
  EXPECT_EQ(a.start_paused, b.start_paused);
  EXPECT_EQ(file.command.torque_limit, bare.command.torque_limit);
  EXPECT_EQ(file.command.timeout, bare.command.timeout);
  EXPECT_EQ(file.frames.prefix, bare.frames.prefix);
  EXPECT_EQ(file.frames.world, bare.frames.world);
  EXPECT_EQ(file.frames.pivot_height, bare.frames.pivot_height);
}

TEST(LoadConfig, OptionalSectionsMayBeOmitted) {
  YAML::Node root = defaultYaml();
  root.remove("simulation");
  root.remove("command");
  root.remove("frames");
  root["mechanism"].remove("rod_inertia");
  const LoadedConfig loaded = loadConfig(root);
  EXPECT_EQ(loaded.config.simulation.physics_rate, SimulationSettings().physics_rate);
  EXPECT_EQ(loaded.config.frames.world, "world");
}

TEST(LoadConfig, MissingRequiredKey) {
  YAML::Node root = defaultYaml();
  root["mechanism"].remove("slider4_mass");
  expectError(root, "mechanism.slider4_mass", "is missing");
  YAML::Node no_state = defaultYaml();
  no_state.remove("initial_state");
  expectError(no_state, "initial_state", "is missing");
}

TEST(LoadConfig, WrongTypes) {
  YAML::Node root = defaultYaml();
  root["mechanism"]["rod_mass"] = "heavy";
  expectError(root, "mechanism.rod_mass", "must be a number, got 'heavy'");

  root = defaultYaml();
  root["initial_state"]["q1"] = YAML::Load("[1, 2]");
  expectError(root, "initial_state.q1", "must be a number, got a list");

  root = defaultYaml();
  root["simulation"] = YAML::Load("[1, 2]");
  expectError(root, "simulation", "must be a map, got a list");

  root = defaultYaml();
  root["simulation"]["publish_clock"] = "sometimes";
  expectError(root, "simulation.publish_clock", "must be true or false, got 'sometimes'");
}

// Every numeric parameter's refusal reads as a sentence: no stray space before ", got" (a range
// without a unit once read "must be in [0, 1000000] , got").
TEST(LoadConfig, RefusalsHaveNoStraySpace) {
  for (const ParameterSpec& p : parameterSchema()) {
    if (!p.choices.empty()) continue;
    YAML::Node root = defaultYaml();
    root[p.section][p.key] = -1e300;
    try {
      loadConfig(root);
    } catch (const ConfigError& e) {
      EXPECT_EQ(std::string(e.what()).find(" , got"), std::string::npos) << e.what();
    } catch (const std::exception&) {
    }
  }
}

TEST(LoadConfig, OutOfRangeValuesNameKeyAndValue) {
  struct Case {
    const char* section;
    const char* key;
    const char* value;
    const char* message;
  };
  const Case cases[] = {
      {"mechanism", "rod_mass", "-1", "must be > 0, got -1"},
      {"mechanism", "slider3_mass", "0", "must be > 0, got 0"},
      {"simulation", "realtime_priority", "100", "must be in [0, 99] (0 = off, else a SCHED_FIFO"},
      {"simulation", "realtime_priority", "-1", "must be in [0, 99]"},
      {"simulation", "realtime_priority", "2.5", "must be a whole number, got 2.5"},
      {"simulation", "lockstep_timeout", "0", "must be in [0.001, 3600] s (wall), got 0"},
      {"simulation", "lockstep_fallback", "halt",
       "unknown lockstep fallback 'halt' (valid: hold, zero)"},
      {"mechanism", "rod_half_length", "-0.25", "must be > 0, got -0.25"},
      {"mechanism", "rod_inertia", "0", "must be > 0, got 0"},
      {"mechanism", "spring_stiffness", "-3", "must be >= 0, got -3"},
      {"mechanism", "gravity", ".nan", "must be finite, got '.nan'"},
      {"initial_state", "u1", ".inf", "must be finite, got '.inf'"},
      // Rates, ratios and periods: documented finite ranges, checked without NaN holes.
      {"simulation", "physics_rate", "0", "must be in [1, 1e+06] Hz, got 0"},
      {"simulation", "physics_rate", "-100", "must be in [1, 1e+06] Hz, got -100"},
      {"simulation", "physics_rate", "1e9", "must be in [1, 1e+06] Hz, got 1e+09"},
      {"simulation", "physics_rate", "1e-6", "must be in [1, 1e+06] Hz, got 1e-06"},
      {"simulation", "publish_rate", "2000", "must be in [0.01, 1000] Hz, got 2000"},
      {"simulation", "publish_rate", "1e-300", "must be in [0.01, 1000] Hz, got 1e-300"},
      {"simulation", "publish_rate", "1e-308", "must be in [0.01, 1000] Hz"},
      {"simulation", "publish_rate", "300", "whole number of physics steps, got 300"},
      {"simulation", "real_time_factor", "-1", "must be in [0.001, 1e+06]"},
      {"simulation", "real_time_factor", "1e-13", "must be in [0.001, 1e+06]"},
      {"simulation", "real_time_factor", "1e300", "must be in [0.001, 1e+06]"},
      // Values whose derived quantities are not finite numbers.
      {"mechanism", "rod_half_length", "1e-200", "give a rod inertia m (2L)^2/12 of 0"},
      {"frames", "world", "mechanism", "one of the mechanism's own frames (a tf loop)"},
      {"command", "torque_limit", "-5", "must be >= 0, got -5"},
      {"command", "timeout", "-0.1", "must be >= 0, got -0.1"},
      {"frames", "world", "''", "must not be empty"},
      {"frames", "prefix", "'robot 1'", "letters, digits, '_' and '/', got 'robot 1'"},
      {"frames", "world", "/world", "must not start with '/'"},
      // The physics options beyond the textbook.
      {"damping", "crank_joint", "-0.5", "must be >= 0, got -0.5"},
      {"damping", "coupler_joint", ".nan", "must be finite, got '.nan'"},
      {"damping", "slider3_joint", "-1", "must be >= 0, got -1"},
      {"damping", "slider4_joint", "fast", "must be a number, got 'fast'"},
      {"command", "motor_no_load_speed", "-10", "must be >= 0, got -10"},
      {"command", "motor_no_load_speed", ".inf", "must be finite, got '.inf'"},
      {"contact", "restitution", "1.5", "must be in [0, 1] (0 plastic, 1 elastic), got 1.5"},
      {"contact", "restitution", ".nan", "must be finite, got '.nan'"},
      {"contact", "gap", "-0.07", "must be >= 0, got -0.07"},
      {"contact", "enabled", "sometimes", "must be true or false, got 'sometimes'"},
      // A standard error the estimator considers (identify writes them): one row per parameter.
      {"uncertainty", "mechanism.rod_mass", "-0.1", "must be in [0, 1e+06], got -0.1"},
      {"uncertainty", "mechanism.spring_stiffness", ".nan", "got '.nan'"},
      {"uncertainty", "friction.crank_joint", ".inf", "got '.inf'"},
      {"uncertainty", "damping.spring", "1e308", "must be in [0, 1e+06], got 1e+308"},
      {"uncertainty", "mechanism.slider4_mass", "small", "must be a number, got 'small'"},
  };
  for (const Case& c : cases) {
    YAML::Node root = defaultYaml();
    root[c.section][c.key] = YAML::Load(c.value);
    expectError(root, std::string(c.section) + "." + c.key, c.message);
  }
}

TEST(LoadConfig, KeysAreNamesEachGivenOnce) {
  expectError(YAML::Load("mechanism: {rod_mass: 1.0, rod_mass: -5}\ninitial_state: {}"),
              "mechanism.rod_mass", "appears twice");
  YAML::Node complex = defaultYaml();
  complex["simulation"][YAML::Load("[a, b]")] = 1;
  expectError(complex, "simulation", "has a key that is not a plain name (a list)");
  expectError(YAML::Load("? [a, b]\n: 1\nmechanism: {}"), "<root>", "not a plain name");
}

TEST(LoadConfig, OptionalSectionWithEveryKeyCommentedOutIsEmpty) {
  YAML::Node root = defaultYaml();
  root["command"] = YAML::Node(YAML::NodeType::Null);
  const Config c = loadConfig(root).config;
  EXPECT_EQ(c.command.torque_limit, CommandSettings().torque_limit);
  root["mechanism"] = YAML::Node(YAML::NodeType::Null);
  expectError(root, "mechanism", "must be a map, got null");  // required: not optional
}

TEST(LoadConfig, DiagnosticsThresholdsAreCheckedByName) {
  YAML::Node root = defaultYaml();
  root["diagnostics"]["overrun_fraction"] = 1.5;
  expectError(root, "diagnostics.overrun_fraction", "must be in [0, 1]");
  root = defaultYaml();
  root["diagnostics"]["late_windows"] = 2.5;
  expectError(root, "diagnostics.late_windows", "must be a whole number of windows, got 2.5");
  root = defaultYaml();
  root["diagnostics"]["late_windows"] = 0;
  expectError(root, "diagnostics.late_windows", "must be in [1, 3600]");
  root = defaultYaml();
  root.remove("diagnostics");
  const Config c = loadConfig(root).config;
  EXPECT_EQ(c.diagnostics.overrun_fraction, 0.05);
  EXPECT_EQ(c.diagnostics.late_windows, 3);
}

// Readings in flight are bounded: 1 MHz readings 10 s late once grew simulate to 1.24 GB.
TEST(LoadConfig, SensorReadingsInFlightAreBounded) {
  YAML::Node root = defaultYaml();
  root["simulation"]["physics_rate"] = 1e6;
  root["sensors"]["enabled"] = true;
  root["sensors"]["rate"] = 1e6;
  root["sensors"]["latency"] = 10.0;
  expectError(root, "sensors.latency", "keeps 10000000 readings in flight, more than 100000");
  root["sensors"]["latency"] = 0.05;  // 50000 in flight: accepted
  EXPECT_NO_THROW(loadConfig(root));
  root["sensors"]["latency_jitter"] = 0.06;  // 110000 with the jitter
  expectError(root, "sensors.latency", "latency_jitter 0.06 s");
}

// A jitter longer than the reading period bunches readings under one stamp: said at start-up.
TEST(LoadConfig, AJitterLongerThanTheReadingPeriodIsAWarning) {
  YAML::Node root = defaultYaml();
  root["sensors"]["enabled"] = true;
  root["sensors"]["rate"] = 100.0;
  root["sensors"]["latency_jitter"] = 0.005;  // half the 10 ms period: fine
  EXPECT_TRUE(loadConfig(root).warnings.empty());
  root["sensors"]["latency_jitter"] = 0.05;  // five periods
  const LoadedConfig loaded = loadConfig(root);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("sensors.latency_jitter 0.05 s is longer than the reading "
                                    "period 0.01 s"),
            std::string::npos)
      << loaded.warnings[0];
}

TEST(LoadConfig, UnknownIntegratorListsTheValidOnes) {
  YAML::Node root = defaultYaml();
  root["simulation"]["integrator"] = "euler";
  expectError(root, "simulation.integrator", "unknown integrator 'euler' (valid: rk4, dopri5)");
}

TEST(LoadConfig, UnknownKeysAreWarningsNamingThem) {
  YAML::Node root = defaultYaml();
  root["mechanism"]["rod_colour"] = "red";
  root["extras"] = 1;
  const LoadedConfig loaded = loadConfig(root);
  ASSERT_EQ(loaded.warnings.size(), 2u);
  const std::string all = loaded.warnings[0] + loaded.warnings[1];
  EXPECT_NE(all.find("'mechanism.rod_colour'"), std::string::npos) << all;
  EXPECT_NE(all.find("'extras'"), std::string::npos) << all;
}

// An uncertainty for a parameter that has none (L is measured, not fitted) or a misspelt one is
// named, as any unknown key is.
TEST(LoadConfig, AnUncertaintyOfNoFittedParameterIsNamed) {
  YAML::Node root = defaultYaml();
  root["uncertainty"]["mechanism.rod_half_length"] = 0.001;
  root["uncertainty"]["mechanism.rod_mas"] = 0.01;
  const LoadedConfig loaded = loadConfig(root);
  ASSERT_EQ(loaded.warnings.size(), 2u);
  const std::string all = loaded.warnings[0] + loaded.warnings[1];
  EXPECT_NE(all.find("'uncertainty.mechanism.rod_half_length'"), std::string::npos) << all;
  EXPECT_NE(all.find("'uncertainty.mechanism.rod_mas'"), std::string::npos) << all;
  EXPECT_NE(loaded.warnings[0].find("a row for each parameter identify fits (mechanism.rod_mass, "),
            std::string::npos)
      << loaded.warnings[0];
}

// Writes `text` to a temporary file (unless it is empty: then `name` is the path) and expects
// loading it to fail with a message holding `expected`.
void expectFileError(const std::string& name, const std::string& text,
                     const std::string& expected) {
  std::string path = name;
  if (!text.empty()) {
    path = ::testing::TempDir() + "/" + name;
    std::ofstream(path) << text;
  }
  try {
    loadConfigFile(path);
    ADD_FAILURE() << path << " accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "file");
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(LoadConfig, UnreadableOrMalformedFile) {
  EXPECT_THROW(loadConfigFile("/nonexistent/mechanism.yaml"), ConfigError);
  expectFileError("malformed.yaml", "mechanism: {rod_mass: [1,\n", "not valid YAML");
  const std::string list_path = ::testing::TempDir() + "/list.yaml";
  std::ofstream(list_path) << "- 1\n- 2\n";
  EXPECT_THROW(loadConfigFile(list_path), ConfigError);
  expectFileError("/etc", "", "not a readable file");
  expectFileError("deep.yaml",
                  "mechanism: " + std::string(5000, '[') + std::string(5000, ']') + "\n",
                  "nested too deeply at line 1");
  expectFileError("two.yaml", "mechanism: {}\n---\nmechanism: {}\n", "holds 2 YAML documents");
  expectFileError("/dev/zero", "", "not a regular file");
  expectFileError("merge_scalar.yaml", "damping: {<<: 3}\n", "a merge key '<<' must name a map");
  // Aliases of aliases: six lines that stand for 10^7 nodes are refused at once (they once kept
  // simulate busy for minutes).
  std::string laughs = "l0: &l0 [a, a, a, a, a, a, a, a, a, a]\n";
  for (int i = 1; i <= 7; ++i)
    laughs += "l" + std::to_string(i) + ": &l" + std::to_string(i) + " [" + [&] {
      std::string items;
      for (int k = 0; k < 10; ++k) items += (k ? ", *l" : "*l") + std::to_string(i - 1);
      return items;
    }() + "]\n";
  expectFileError("laughs.yaml", laughs, "aliases of aliases");
  // An alias inside its own anchor (a cycle) once overflowed the stack.
  expectFileError("cycle.yaml", "a: &a\n  x: *a\nmechanism:\n  <<: *a\n  rod_mass: 1.0\n",
                  "an alias inside its own anchor");
  std::string chain = "a0: &a0 {rod_mass: 1.0}\n";
  for (int i = 1; i <= 2000; ++i)
    chain += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " {<<: *a" +
             std::to_string(i - 1) + "}\n";
  expectFileError("chain.yaml", chain, "nests deeper than 64 levels");
}

// A merge key reads as rosparam (PyYAML) reads it: the node and the offline tools see one
// config (simulate used to warn "unknown key 'damping.<<'" and run undamped).
TEST(LoadConfig, MergeKeysAreExpandedAsRosparamExpandsThem) {
  std::ifstream in(test::configPath("mechanism.yaml"));
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const size_t damping = text.find("damping:");
  const size_t contact = text.find("contact:");
  ASSERT_NE(damping, std::string::npos);
  text.replace(damping, contact - damping,
               "base_damping: &bd {crank_joint: 0.5, slider3_joint: 2.0}\n"
               "damping: {<<: *bd, slider3_joint: 3.0}\n");
  const std::string path = ::testing::TempDir() + "/merge.yaml";
  std::ofstream(path) << text;
  const LoadedConfig loaded = loadConfigFile(path);
  EXPECT_EQ(loaded.config.mechanism.damping.crank_joint, 0.5);    // from the anchor
  EXPECT_EQ(loaded.config.mechanism.damping.slider3_joint, 3.0);  // its own entry wins
  EXPECT_EQ(loaded.config.mechanism.damping.coupler_joint, 0.0);  // in neither: the default
  ASSERT_EQ(loaded.warnings.size(), 1u);  // the anchor's own section is an unknown key
  EXPECT_NE(loaded.warnings[0].find("'base_damping'"), std::string::npos) << loaded.warnings[0];
}

}  // namespace
}  // namespace kane_sim
