// Sweeps (sim/sweep.h): the grid and CSV plans, each case's config through the one loader,
// results in case order whatever the threads, and a case equal to the same single run.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "kane_sim/sim/simulator.h"
#include "kane_sim/sim/sweep.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

YAML::Node baseYaml() { return loadYamlFile(test::configPath("mechanism.yaml")); }

TEST(Sweep, AxisGivesCountValuesFromStartToStop) {
  const SweepAxis a = parseSweepAxis("mechanism.spring_stiffness=100:300:5");
  EXPECT_EQ(a.key, "mechanism.spring_stiffness");
  ASSERT_EQ(a.values.size(), 5u);
  EXPECT_EQ(a.values.front(), 100.0);
  EXPECT_EQ(a.values[2], 200.0);
  EXPECT_EQ(a.values.back(), 300.0);
  EXPECT_EQ(parseSweepAxis("initial_state.q1=0.3:9:1").values, std::vector<double>{0.3});
}

TEST(Sweep, BadAxesAreRefusedNamingThePart) {
  const char* bad[] = {"spring_stiffness=1:2:3", "mechanism.k=1:2",     "mechanism.k=1:2:0",
                       "mechanism.k=1:x:3",      "mechanism.k=1:2:2.5", "mechanism.k",
                       "mechanism.k=nan:1:2",    "a.b.c=1:2:3"};
  for (const char* spec : bad) EXPECT_THROW(parseSweepAxis(spec), std::invalid_argument) << spec;
  try {
    parseSweepAxis("mechanism.gravity=1:x:3");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mechanism.gravity STOP: 'x'"), std::string::npos)
        << e.what();
  }
}

TEST(Sweep, GridIsEveryCombinationLastAxisFastest) {
  const SweepPlan plan = sweepGrid(
      {parseSweepAxis("mechanism.rod_mass=1:2:2"), parseSweepAxis("initial_state.u1=0:2:3")});
  ASSERT_EQ(plan.cases.size(), 6u);
  EXPECT_EQ(plan.cases[0], (std::vector<double>{1, 0}));
  EXPECT_EQ(plan.cases[1], (std::vector<double>{1, 1}));
  EXPECT_EQ(plan.cases[3], (std::vector<double>{2, 0}));
  EXPECT_EQ(plan.cases[5], (std::vector<double>{2, 2}));
  EXPECT_THROW(sweepGrid({parseSweepAxis("mechanism.rod_mass=1:2:2"),
                          parseSweepAxis("mechanism.rod_mass=1:2:2")}),
               std::invalid_argument);
}

TEST(Sweep, CsvPlanReadsKeysAndRowsAndNamesBadLines) {
  std::istringstream good(
      "# a comment\nmechanism.gravity, damping.crank_joint\n9.81,0\n1.62,0.1\n");
  const SweepPlan plan = sweepFromCsv(good);
  EXPECT_EQ(plan.keys, (std::vector<std::string>{"mechanism.gravity", "damping.crank_joint"}));
  ASSERT_EQ(plan.cases.size(), 2u);
  EXPECT_EQ(plan.cases[1], (std::vector<double>{1.62, 0.1}));
  std::istringstream short_row("mechanism.gravity,mechanism.rod_mass\n9.81\n");
  try {
    sweepFromCsv(short_row);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("line 2 has 1 values for 2 keys"), std::string::npos);
  }
  std::istringstream empty("mechanism.gravity\n");
  EXPECT_THROW(sweepFromCsv(empty), std::invalid_argument);
}

TEST(Sweep, CaseConfigsGoThroughTheLoader) {
  const SweepPlan plan = sweepGrid({parseSweepAxis("damping.crank_joint=0:0.2:3")});
  EXPECT_EQ(sweepCaseConfig(baseYaml(), plan, 2).mechanism.damping.crank, 0.2);
  const SweepPlan negative = sweepGrid({parseSweepAxis("mechanism.rod_mass=-1:1:2")});
  try {
    sweepCaseConfig(baseYaml(), negative, 0);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "mechanism.rod_mass");
  }
  const SweepPlan typo = sweepGrid({parseSweepAxis("mechanism.rod_mas=1:2:2")});
  EXPECT_THROW(sweepCaseConfig(baseYaml(), typo, 0), ConfigError);
}

// The results come back in case order, each equal to the same case run alone (bit for bit:
// the same driver, the same steps), and a refused case is recorded without stopping the rest.
TEST(Sweep, ResultsAreInCaseOrderAndEqualSingleRuns) {
  const SweepPlan plan = sweepGrid({parseSweepAxis("mechanism.spring_stiffness=50:400:8"),
                                    parseSweepAxis("initial_state.u1=-2:2:3")});
  SweepSettings settings;
  settings.duration = 2.0;
  settings.torque = TorqueProfile::sine(5.0, 0.5, 1.0);
  settings.jobs = 3;
  const std::vector<SweepResult> results = runSweep(baseYaml(), plan, settings);
  ASSERT_EQ(results.size(), 24u);
  for (size_t i = 0; i < results.size(); ++i) {
    const Config c = sweepCaseConfig(baseYaml(), plan, i);
    EXPECT_EQ(c.mechanism.spring_stiffness, plan.cases[i][0]);
    const SweepResult alone = runSweepCase(c, settings);
    ASSERT_EQ(results[i].status, "ok") << results[i].error;
    EXPECT_EQ(results[i].final_state.q1, alone.final_state.q1) << i;
    EXPECT_EQ(results[i].final_state.u2, alone.final_state.u2) << i;
    EXPECT_EQ(results[i].steps, 2000u);
    EXPECT_EQ(results[i].time, 2.0);
    EXPECT_GE(results[i].max_abs_q1, std::abs(results[i].final_state.q1));
    EXPECT_LT(results[i].ledger_error, 1e-6) << "rk4 at 1 kHz on a gentle drive";
  }
  // Stiffnesses that rk4 at 1 kHz cannot integrate are refused by the loader's check, per case.
  const SweepPlan stiff = sweepGrid({parseSweepAxis("mechanism.spring_stiffness=200:1e9:2")});
  const std::vector<SweepResult> mixed = runSweep(baseYaml(), stiff, settings);
  EXPECT_EQ(mixed[0].status, "ok");
  EXPECT_EQ(mixed[1].status, "config_refused");
  EXPECT_NE(mixed[1].error.find("spring_stiffness"), std::string::npos) << mixed[1].error;
  // Its row keeps the columns, with nothing where nothing ran.
  std::ostringstream rows;
  writeSweepCsvHeader(rows, stiff);
  writeSweepCsvRow(rows, stiff, 0, mixed[0]);
  writeSweepCsvRow(rows, stiff, 1, mixed[1]);
  std::istringstream lines(rows.str());
  std::string header, ok_row, refused_row;
  std::getline(lines, header);
  std::getline(lines, ok_row);
  std::getline(lines, refused_row);
  const auto fields = [](const std::string& line) {
    return std::count(line.begin(), line.end(), ',') + 1;
  };
  EXPECT_EQ(fields(ok_row), fields(header));
  EXPECT_EQ(fields(refused_row), fields(header));
  EXPECT_EQ(refused_row, "1,1e+09,config_refused,,,,,,,,,,,,,,");
}

}  // namespace
}  // namespace kane_sim
