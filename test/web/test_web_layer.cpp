// The browser's entry points, natively (the same C++ the WebAssembly module runs): one run as
// simulate's rows, the live session, the drawing, the schema, and the number text the module
// builds without floating-point to_chars.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "kane_sim/config/load_config.h"
#include "kane_sim/format_number.h"
#include "kane_sim/sim/csv_format.h"
#include "kane_sim/sim/profile_commands.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/web/live_session.h"
#include "kane_sim/web/run_case.h"
#include "kane_sim/web/schema_json.h"

namespace kane_sim {
namespace {

std::string defaultYaml() {
  std::ifstream in(std::string(KANE_SIM_CONFIG_DIR) + "/mechanism.yaml");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

size_t column(const web::CaseTable& t, const std::string& name) {
  for (size_t i = 0; i < t.columns.size(); ++i)
    if (t.columns[i] == name) return i;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

TEST(RunCase, RowsAreSimulatesRowsOnTheOutputGrid) {
  const web::CaseTable t =
      web::runCase(defaultYaml(), "mechanism.yaml", 2.0, TorqueProfile::sine(1.0, 0.5, 0.0), 10.0);
  ASSERT_EQ(t.rows(), 21u);  // t = 0, 0.1, ..., 2
  EXPECT_EQ(t.columns.front(), "t");
  EXPECT_EQ(t.columns.size(), csvColumns().size());
  EXPECT_DOUBLE_EQ(t.values[20 * t.columns.size()], 2.0);
  EXPECT_TRUE(t.refused.empty());
  // The same driver and loop as a run made here step by step: the same bits.
  SimDriver driver(loadConfig(loadYamlText(defaultYaml(), "x")).config, [](const SimEvent&) {});
  const TorqueProfile profile = TorqueProfile::sine(1.0, 0.5, 0.0);
  ProfileCommands commands(profile, driver.config().command.timeout);
  commands.update(driver);
  for (int i = 0; i < 2000; ++i) {
    ASSERT_TRUE(driver.step());
    commands.update(driver);
  }
  const Snapshot end = driver.snapshot();
  const size_t last = 20 * t.columns.size();
  EXPECT_EQ(t.values[last + column(t, "q1")], end.state.q1);
  EXPECT_EQ(t.values[last + column(t, "u2")], end.state.u2);
}

TEST(RunCase, RefusesWithTheLoadersWords) {
  try {
    web::runCase("mechanism: {rod_mass: -1}", "the pasted config", 1.0, std::nullopt, 10.0);
    FAIL() << "a negative mass ran";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("mechanism.rod_mass"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("-1"), std::string::npos) << e.what();
  }
  try {
    web::runCase("a: [unclosed", "the pasted config", 1.0, std::nullopt, 10.0);
    FAIL() << "broken YAML ran";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'the pasted config' is not valid YAML"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(web::runCase(std::string(2 << 20, '#'), "big", 1.0, std::nullopt, 10.0),
               ConfigError);
}

TEST(RunCase, RefusesGridsAndHugeRunsByName) {
  const std::string yaml = defaultYaml();
  for (double bad : {std::nan(""), -1.0, 1e308, std::numeric_limits<double>::infinity()}) {
    try {
      web::runCase(yaml, "c", bad, std::nullopt, 10.0);
      FAIL() << "duration " << bad << " ran";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("duration"), std::string::npos) << e.what();
    }
    try {
      web::runCase(yaml, "c", 1.0, std::nullopt, bad);
      FAIL() << "outputRate " << bad << " ran";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("outputRate"), std::string::npos) << e.what();
    }
  }
  try {
    web::runCase(yaml, "c", 10000.0, std::nullopt, 1000.0);  // 10^7 rows
    FAIL() << "a run past the row bound started";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("at most"), std::string::npos) << e.what();
  }
}

TEST(RunCase, StopsWhenAsked) {
  std::atomic<bool> stop{true};
  const web::CaseTable t = web::runCase(defaultYaml(), "c", 5.0, std::nullopt, 10.0, &stop);
  EXPECT_TRUE(t.stopped);
  EXPECT_EQ(t.rows(), 1u);  // the start's row only
}

TEST(LiveSession, AdvancesRefusesBadInputAndKeepsItsState) {
  web::LiveSession session(defaultYaml(), "mechanism.yaml");
  const std::vector<double> rows = session.advance(0.5, 1.0, 100);
  const size_t width = csvColumns().size();
  ASSERT_EQ(rows.size(), 5 * width);  // every 100 steps of 500
  EXPECT_NEAR(session.time(), 0.5, 1e-12);
  const std::vector<double> before = session.row();
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_THROW(session.advance(0.1, bad, 1), std::invalid_argument);
  for (double bad : {-1.0, 61.0, std::nan(""), 1e308})
    EXPECT_THROW(session.advance(bad, 0.0, 1), std::invalid_argument);
  EXPECT_THROW(session.advance(0.1, 0.0, 0), std::invalid_argument);
  EXPECT_EQ(session.row(), before);  // nothing stepped, nothing lost
  const std::vector<double> start = web::LiveSession(defaultYaml(), "x").row();
  session.reset();  // the config's initial state; sim time runs on, as the node's clock does
  EXPECT_EQ(session.row()[1], start[1]);  // q1
  EXPECT_EQ(session.row()[2], start[2]);  // q2
  EXPECT_EQ(session.row()[3], 0.0);       // u1
}

TEST(LiveSession, ParametersChangeAsTheNodesDoOrAreRefusedWithTheLoadersWords) {
  web::LiveSession session(defaultYaml(), "mechanism.yaml");
  session.advance(0.2, 0.0, 200);
  EXPECT_EQ(session.setParameter("spring_stiffness", 300.0), "");
  EXPECT_EQ(session.config().mechanism.spring_stiffness, 300.0);
  EXPECT_NE(session.configYaml().find("300"), std::string::npos);
  const std::string refused = session.setParameter("spring_stiffness", -5.0);
  EXPECT_NE(refused.find("mechanism.spring_stiffness"), std::string::npos) << refused;
  EXPECT_EQ(session.config().mechanism.spring_stiffness, 300.0);
  EXPECT_NE(session.setParameter("no_such_thing", 1.0).find("not a reconfigurable"),
            std::string::npos);
  EXPECT_NE(session.setParameter("spring_stiffness", std::nan("")), "");
  const std::vector<double> before = session.row();
  EXPECT_EQ(session.setMode("position"), "");
  EXPECT_EQ(session.config().command.mode, CommandMode::kPosition);
  // A new driver that goes on: the same time, state and ledger (the columns up to the ledger's).
  EXPECT_EQ(session.time(), 0.2);
  const std::vector<double> after = session.row();
  for (const char* name : {"t", "q1", "q2", "u1", "u2", "motor_work", "dissipated_energy"}) {
    size_t i = 0;
    while (csvColumns()[i].name != name) ++i;
    EXPECT_EQ(after[i], before[i]) << name;
  }
  EXPECT_NE(session.setMode("sideways").find("command.mode"), std::string::npos);
}

// The panel's initial state: the motion restarts there (t = 0, the ledger from zero), through the
// loader's checks; a refusal names the key and changes nothing.
TEST(LiveSession, TheInitialStateRestartsTheMotionOrIsRefusedNamingTheKey) {
  web::LiveSession session(defaultYaml(), "mechanism.yaml");
  session.advance(0.3, 2.0, 300);
  ASSERT_EQ(session.setInitialState("q1", 1.0), "");
  EXPECT_EQ(session.time(), 0.0);
  EXPECT_EQ(session.config().initial_state.q1, 1.0);
  EXPECT_EQ(session.row()[1], 1.0);  // q1
  EXPECT_NE(session.configYaml().find("q1: 1"), std::string::npos) << session.configYaml();
  ASSERT_EQ(session.setInitialState("u1", -2.5), "");
  EXPECT_EQ(session.row()[1], 1.0);
  EXPECT_EQ(session.row()[3], -2.5);  // u1
  const std::vector<double> kept = session.row();
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(), -1e308 * 10}) {
    const std::string refused = session.setInitialState("q2", bad);
    EXPECT_NE(refused.find("initial_state.q2"), std::string::npos) << refused;
  }
  EXPECT_NE(session.setInitialState("q3", 1.0).find("'q3' is not a key of initial_state"),
            std::string::npos);
  EXPECT_NE(session.setInitialState("", 1.0).find("is not a key"), std::string::npos);
  EXPECT_EQ(session.row(), kept);  // nothing changed
  EXPECT_EQ(session.config().initial_state.u1, -2.5);
  // Contact on: slider 4 set inside the gap is refused with the loader's words.
  YAML::Node tree = YAML::Load(defaultYaml());
  tree["contact"]["enabled"] = true;
  web::LiveSession touching(YAML::Dump(tree), "contact.yaml");
  const double q2 = touching.config().initial_state.q2;
  const std::string refused = touching.setInitialState("q2", q2 - 0.29);
  EXPECT_NE(refused.find("contact.gap"), std::string::npos) << refused;
}

TEST(Outlines, RodsRunFromPinToPinAndSlidersSitOnTheRail) {
  web::LiveSession session(defaultYaml(), "mechanism.yaml");
  const double L = session.config().mechanism.rod_half_length;
  const double q1 = 0.4;
  const JointValues joints = session.jointsAt(q1, 1.2);
  const auto origins = session.originsAt(joints);
  ASSERT_EQ(origins.size(), 4u);
  // rod1's frame at O, rod2's at A = 2L (cos q1, sin q1), slider3 at B = (4L cos q1, 0),
  // slider4 at C = (q2, 0): the textbook's kinematics (eqs 1-4).
  EXPECT_NEAR(origins[0].second.norm(), 0.0, 1e-12);
  EXPECT_NEAR(origins[1].second.x(), 2 * L * std::cos(q1), 1e-12);
  EXPECT_NEAR(origins[1].second.y(), 2 * L * std::sin(q1), 1e-12);
  EXPECT_NEAR(origins[2].second.x(), 4 * L * std::cos(q1), 1e-12);
  EXPECT_NEAR(origins[2].second.y(), 0.0, 1e-12);
  EXPECT_NEAR(origins[3].second.x(), 1.2, 1e-12);
  const auto outlines = session.outlinesAt(joints);
  ASSERT_EQ(outlines.size(), 4u);
  for (const auto& o : outlines) EXPECT_GE(o.polygon.size(), 4u) << o.link;
  // rod 1's outline reaches from O to A along the rod.
  double reach = 0.0;
  for (const auto& p : outlines[0].polygon)
    reach = std::max(reach, p.dot(Eigen::Vector2d(std::cos(q1), std::sin(q1))));
  EXPECT_NEAR(reach, 2 * L, 0.02);
}

TEST(SchemaJson, CarriesThePanelsRowsAndTheColumnsGroups) {
  const Config config = loadConfig(loadYamlText(defaultYaml(), "x")).config;
  const std::string json = web::schemaJson(config);
  EXPECT_NE(json.find("\"name\":\"spring_stiffness\""), std::string::npos);
  EXPECT_NE(json.find("\"key\":\"mechanism.spring_stiffness\""), std::string::npos);
  EXPECT_NE(json.find("\"group\":\"power\""), std::string::npos);
  EXPECT_NE(json.find("\"joints\":[\"crank_joint\""), std::string::npos);
  EXPECT_EQ(json.find("inf"), std::string::npos);  // JSON has no inf: null stands for it
  EXPECT_EQ(web::jsonString("a\"b\\c\n\x01"), "\"a\\\"b\\\\c\\n\\u0001\"");
}

// The WebAssembly build's standard library has no floating-point to_chars: its numbers come
// from printf's digits. They must be to_chars's text exactly (the CSV, every message).
TEST(FormatNumber, PrintfDigitsGiveToCharsTextExactly) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> decade(-30, 30);
  long checked = 0;
  const auto check = [&checked](double v) {
    char a[32], b[32];
    const std::string expected(a, std::to_chars(a, a + 32, v).ptr);
    const std::string got(b, shortestCharsByPrintf(b, v));
    ASSERT_EQ(got, expected);
    ++checked;
  };
  for (double v : {0.0, -0.0, 1.0, 10.0, 1200000.0, 1e20, 1e21, 1e22, 123456789012.0, 1e-4, 1e-5,
                   0.1, 5e-324, 1.7976931348623157e308, 1e16, 12345678901234567.0,
                   9007199254740993.0, std::numeric_limits<double>::infinity(), std::nan("")}) {
    check(v);
    check(-v);
  }
  for (int i = 0; i < 50000; ++i) {
    std::uint64_t bits = random();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    check(v);
    const double w = std::pow(10.0, decade(random));
    check(w);
    check(std::round(w * 1000) / 1000);  // short decimals, as configs hold
  }
  EXPECT_EQ(checked, 150000 + 38);
}

}  // namespace
}  // namespace kane_sim
