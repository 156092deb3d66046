// Sweeps (sim/sweep.h): the grid and CSV plans, each case's config through the one loader,
// results in case order whatever the threads, and a case equal to the same single run.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>

#include "kane_sim/batch/lanes.h"
#include "kane_sim/config/load_config.h"
#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/model/math_functions.h"
#include "kane_sim/sim/parallel.h"
#include "kane_sim/sim/simulator.h"
#include "kane_sim/sim/state_rates.h"
#include "kane_sim/sim/sweep.h"
#include "kane_sim/sim/worker_pool.h"
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
  EXPECT_EQ(sweepCaseConfig(baseYaml(), plan, 2).mechanism.damping.crank_joint, 0.2);
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

// Physics and initial-state keys take the direct path (the base loaded once, each case's
// numbers stored by the loader's rules): every schema value equal to the loader's config of the
// same case, the rod's inertia derived alike, and a refusal in the loader's words.
TEST(Sweep, DirectCaseConfigsAreTheLoadersConfigsAndWords) {
  SweepPlan plan;
  plan.keys = {"mechanism.rod_mass", "mechanism.spring_stiffness", "initial_state.q1"};
  plan.cases = {{1.3, 150.0, 0.2}, {0.7, 250.0, -0.4},         {-1.0, 150.0, 0.2},
                {1.0, 0.0, 0.2},   {1.0, 150.0, std::nan("")}, {1e308, 150.0, 0.2}};
  const SweepCaseConfigs direct(baseYaml(), plan);
  const YAML::Node base = baseYaml();
  for (size_t i = 0; i < plan.cases.size(); ++i) {
    std::string loader_error, direct_error;
    Config from_loader, from_direct;
    try {
      from_loader = sweepCaseConfig(base, plan, i);
    } catch (const ConfigError& e) {
      loader_error = e.what();
    }
    try {
      from_direct = direct.at(base, i);
    } catch (const ConfigError& e) {
      direct_error = e.what();
    }
    EXPECT_EQ(direct_error, loader_error) << "case " << i;
    if (!loader_error.empty()) continue;
    for (const ParameterSpec& spec : parameterSchema()) {
      if (spec.field.number || spec.field.whole) {
        EXPECT_EQ(numericValue(spec, from_direct), numericValue(spec, from_loader))
            << spec.path() << ", case " << i;
      }
    }
  }
  // Three of six refused (a negative mass, k 0, q1 NaN: the loader's checks) and the mass of
  // 1e308 by the start-up check: the paths agree on each, word for word (above).
  EXPECT_THROW(direct.at(base, 2), ConfigError);
  EXPECT_THROW(direct.at(base, 5), ConfigError);
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

// Every column of a row but wall_time.
std::vector<double> rowValues(const SweepResult& r) {
  std::vector<double> values{r.final_state.q1, r.final_state.q2, r.final_state.u1, r.final_state.u2,
                             r.time};
  for (const SweepColumn* c = sweepColumnsBegin(); c != sweepColumnsEnd(); ++c)
    if (std::string(c->name) != "wall_time") values.push_back(c->value(r));
  return values;
}

// A grid that reaches every lane path: every variant of the equations (no resistance, dampers,
// dampers and friction, friction alone: the deterministic tanh per lane), slider crossings, a step
// the Simulator refuses mid-run (6000 N m from 0.6 s spin the crank past 1 rad a step), a motor
// line (not a lane case: it runs alone), a refused config, and more cases than a chunk.
SweepPlan laneGrid() {
  SweepPlan plan;
  plan.keys = {"damping.slider4_joint",      "command.torque_limit", "command.motor_no_load_speed",
               "mechanism.spring_stiffness", "initial_state.u2",     "initial_state.u1",
               "friction.slider3_joint"};
  for (int i = 0; i < 150; ++i)
    plan.cases.push_back({i % 3 == 0 ? 0.0 : 0.5 * (i % 5), i == 7 ? 8000.0 : 10.0,
                          i % 11 == 5 ? 40.0 : 0.0, i == 13 ? 1e9 : 50.0 + 3.0 * i,
                          i % 4 == 1 ? -8.0 : 0.0, 0.0, i % 7 < 3 ? 0.0 : 0.3 * (i % 7)});
  return plan;
}

// Back and forth, then hard one way: the 10 N m limit of most cases clamps it; case 7's 8000 N m
// limit lets 6000 N m through.
TorqueProfile laneDrive() {
  return TorqueProfile::table({{0.0, 300.0}, {0.3, -300.0}, {0.6, 6000.0}});
}

TEST(Sweep, LanesEqualTheSingleRunsBitForBitOnEveryInstructionSet) {
  const SweepPlan plan = laneGrid();
  SweepSettings settings;
  settings.duration = 2.0;
  settings.torque = laneDrive();
  settings.jobs = 2;
  settings.simd = "off";
  const std::vector<SweepResult> alone = runSweep(baseYaml(), plan, settings);
  EXPECT_EQ(alone[7].status, "step_refused") << alone[7].error;
  EXPECT_EQ(alone[13].status, "config_refused");
  EXPECT_GT(std::count_if(alone.begin(), alone.end(),
                          [](const SweepResult& r) { return r.slider_crossings > 0; }),
            10);
  for (LaneArch arch : {LaneArch::kScalar, LaneArch::kSse2, LaneArch::kAvx2, LaneArch::kAvx512}) {
    if (!laneArchAvailable(arch)) continue;
    settings.simd = laneArchName(arch);
    const std::vector<SweepResult> lanes = runSweep(baseYaml(), plan, settings);
    ASSERT_EQ(lanes.size(), alone.size());
    for (size_t i = 0; i < lanes.size(); ++i) {
      EXPECT_EQ(lanes[i].status, alone[i].status) << settings.simd << " case " << i;
      EXPECT_EQ(lanes[i].error, alone[i].error) << settings.simd << " case " << i;
      EXPECT_EQ(rowValues(lanes[i]), rowValues(alone[i])) << settings.simd << " case " << i;
    }
  }
}

// The equations' sin, cos and tanh (model/math_functions.h, SLEEF's deterministic functions)
// return the scalar form's bits at every width this CPU has, over angles of every magnitude a
// run can reach and beyond (to 1e300), tiny and subnormal values, signed zeros, infinities and
// NaN; and they are within 4 ulp of libm's (SLEEF's bound is 3.5) where the motion lives.
TEST(LaneMath, EveryWidthGivesTheScalarFormsBitsAndLibmsValuesTo4Ulp) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-310.0, 300.0);
  std::vector<double> x = {0.0,
                           -0.0,
                           1e-320,
                           -4.9e-324,
                           1e300,
                           -1e308,
                           std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN(),
                           M_PI,
                           -M_PI / 2,
                           710.0};
  for (int i = 0; i < 100000; ++i)
    x.push_back(unit(rng) * (i % 2 ? 1e4 : std::pow(10.0, exponent(rng))));
  const LaneMathValues scalar = laneMathFunctions(LaneArch::kScalar, x);
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  for (std::size_t i = 0; i < x.size(); ++i) {
    double s, c;
    math::sinCos(x[i], &s, &c);
    ASSERT_TRUE(same(scalar.sines[i], s) && same(scalar.cosines[i], c) &&
                same(scalar.tanhs[i], math::tanh(x[i])))
        << "the scalar lanes call the equations' functions, at " << x[i];
  }
  for (LaneArch arch : {LaneArch::kSse2, LaneArch::kAvx2, LaneArch::kAvx512}) {
    if (!laneArchAvailable(arch)) continue;
    const LaneMathValues wide = laneMathFunctions(arch, x);
    int differing = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      differing += !same(wide.sines[i], scalar.sines[i]) ||
                   !same(wide.cosines[i], scalar.cosines[i]) ||
                   !same(wide.tanhs[i], scalar.tanhs[i]);
    EXPECT_EQ(differing, 0) << laneArchName(arch) << ": values differing from the scalar form";
  }
  const auto ulps = [](double got, double want) {
    return std::abs(got - want) / (std::nextafter(std::abs(want), INFINITY) - std::abs(want));
  };
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(std::abs(x[i]) <= 1e4) || std::abs(x[i]) < 1e-300) continue;
    // Near a zero of sin or cos an ulp of the result is tiny; measure against |result| >= 1e-3.
    if (std::abs(std::sin(x[i])) > 1e-3)
      worst = std::max(worst, ulps(scalar.sines[i], std::sin(x[i])));
    if (std::abs(std::cos(x[i])) > 1e-3)
      worst = std::max(worst, ulps(scalar.cosines[i], std::cos(x[i])));
    worst = std::max(worst, ulps(scalar.tanhs[i], std::tanh(x[i])));
  }
  std::cout << "sin, cos, tanh against libm's: at most " << worst << " ulp\n";
  EXPECT_LE(worst, 4.0);
}

// `centre` and the `ulps` doubles on each side of it, into *x: where a function's reduction
// changes hands, the arguments a rounding difference would show at.
void addAround(std::vector<double>* x, double centre, int ulps) {
  double up = centre, down = centre;
  for (int i = 0; i < ulps; ++i) {
    x->push_back(up = std::nextafter(up, INFINITY));
    x->push_back(down = std::nextafter(down, -INFINITY));
  }
  x->push_back(centre);
}

// The scalar sincos is SLEEF's deterministic algorithm written out so that it inlines
// (model/math_functions.h): bit for bit the library's own SSE2 function wherever it answers
// (|x| < 1e14), checked densely where the reduction changes hands: around every multiple of pi/4
// to 10 pi, the switch from the two-part to the four-part reduction at 15, a million turns of
// the crank, the library's takeover at 1e14; random angles of every magnitude; signed zeros,
// subnormals, infinities and NaN. One coefficient's last digit changed fails it.
TEST(LaneMath, TheWrittenOutSincosIsTheLibrarysBitForBit) {
  std::vector<double> x = {0.0,
                           -0.0,
                           4.9e-324,
                           -4.9e-324,
                           1e-310,
                           1e-300,
                           -1e-20,
                           std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()};
  const auto around = [&x](double centre, int ulps) { addAround(&x, centre, ulps); };
  for (int k = -40; k <= 40; ++k) around(k * M_PI / 4, 300);
  for (double centre : {15.0, -15.0, 2 * M_PI * 1e6, 1e14, -1e14}) around(centre, 3000);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> near(-16.0, 16.0), exponent(-300.0, 15.0);
  for (int i = 0; i < 300000; ++i) {
    x.push_back(near(rng));
    x.push_back((i % 2 ? 1 : -1) * std::pow(10.0, exponent(rng)));
  }
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  int differing = 0;
  for (double v : x) {
    double s, c;
    math::sinCos(v, &s, &c);
    const Sleef___m128d_2 library = Sleef_cinz_sincosd2_u35sse2(_mm_set_sd(v));
    const bool equal = same(s, _mm_cvtsd_f64(library.x)) && same(c, _mm_cvtsd_f64(library.y));
    if (!equal && ++differing <= 5)
      ADD_FAILURE() << "at x = " << v << ": " << s << ", " << c << " against the library's "
                    << _mm_cvtsd_f64(library.x) << ", " << _mm_cvtsd_f64(library.y);
  }
  EXPECT_EQ(differing, 0) << "of " << x.size() << " arguments";
}

// The scalar tanh is SLEEF's deterministic tanh written out (model/math_functions.h): bit for
// bit the library's own SSE2 function for every argument, checked densely where the reduction
// changes hands (2|x| / ln 2 at a half-integer: q steps), at q = 0's edge, at the saturation
// (18.714973875) and at the shortcuts' edges (0.17: the unreduced form), on random arguments of
// every magnitude; signed zeros, subnormals, infinities and NaN (the library's NaN: every bit
// set).
TEST(LaneMath, TheWrittenOutTanhIsTheLibrarysBitForBit) {
  std::vector<double> x = {0.0,
                           -0.0,
                           4.9e-324,
                           -4.9e-324,
                           1e-310,
                           -1e-300,
                           1e300,
                           -1e308,
                           std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN(),
                           -std::numeric_limits<double>::quiet_NaN()};
  const auto around = [&x](double centre, int ulps) { addAround(&x, centre, ulps); };
  for (int k = 0; k <= 60; ++k) {
    around((k + 0.5) * M_LN2 / 2, 300);
    around(-(k + 0.5) * M_LN2 / 2, 300);
  }
  for (double centre : {18.714973875, -18.714973875, 0.17, -0.17, 1e-8, 1.0}) around(centre, 3000);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> near(-20.0, 20.0), exponent(-320.0, 308.0);
  for (int i = 0; i < 300000; ++i) {
    x.push_back(near(rng));
    x.push_back((i % 2 ? 1 : -1) * std::pow(10.0, exponent(rng)));
  }
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  int differing = 0;
  for (double v : x) {
    const double library = _mm_cvtsd_f64(Sleef_cinz_tanhd2_u35sse2(_mm_set_sd(v)));
    if (!same(math::tanh(v), library) && ++differing <= 5)
      ADD_FAILURE() << "at x = " << v << ": " << math::tanh(v) << " against the library's "
                    << library;
  }
  EXPECT_EQ(differing, 0) << "of " << x.size() << " arguments";
}

// The friction laws' tanh two values at once (one SSE2 register): each the one-value form's
// bits, whatever the other lane holds (NaN and infinities included): both lanes in the same
// shortcut (saturated, unreduced) or in different ones.
TEST(LaneMath, TanhPairGivesEachValueTheOneValueCallsBits) {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> exponent(-320.0, 310.0);
  std::vector<double> x = {0.0,
                           -0.0,
                           4.9e-324,
                           18.714973875,
                           -18.714973876,
                           std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()};
  for (int i = 0; i < 200000; ++i)
    x.push_back((i % 2 ? 1 : -1) * std::pow(10.0, exponent(rng) / 20.0 - 5.0 * (i % 3)));
  std::uniform_real_distribution<double> either_side(-0.3, 0.3), saturating(18.0, 20.0);
  for (int i = 0; i < 20000; ++i) x.push_back(i % 2 ? either_side(rng) : saturating(rng));
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  int differing = 0;
  for (std::size_t i = 0; i + 1 < x.size(); ++i) {
    double a, b;
    math::tanhPair(x[i], x[x.size() - 1 - i], &a, &b);
    differing += !same(a, math::tanh(x[i])) || !same(b, math::tanh(x[x.size() - 1 - i]));
  }
  EXPECT_EQ(differing, 0);
}

TEST(Sweep, VectorTrigDiffersFarLessThanTheIntegratorsOwnError) {
  // xsimd's sin and cos round differently from libm's, at every stage; sensitive (undamped)
  // motion grows that. The yardstick: rk4's own error, the single run at h against h/2.
  const SweepPlan plan = laneGrid();
  SweepSettings settings;
  settings.duration = 2.0;
  settings.torque = laneDrive();
  settings.simd = "off";
  const std::vector<SweepResult> alone = runSweep(baseYaml(), plan, settings);
  settings.simd = "auto";
  settings.vector_trig = true;
  const std::vector<SweepResult> fast = runSweep(baseYaml(), plan, settings);
  int compared = 0;
  double worst = 0.0;
  for (size_t i = 0; i < plan.cases.size(); ++i) {
    if (alone[i].status != "ok") continue;
    Config finer = sweepCaseConfig(baseYaml(), plan, i);
    finer.simulation.physics_rate *= 2;
    const SweepResult half_step = runSweepCase(finer, settings);
    const auto distance = [](const SweepResult& a, const SweepResult& b) {
      return std::abs(a.final_state.q1 - b.final_state.q1) +
             std::abs(a.final_state.u1 - b.final_state.u1) +
             std::abs(a.final_state.q2 - b.final_state.q2) +
             std::abs(a.final_state.u2 - b.final_state.u2);
    };
    const double integrator_error = distance(half_step, alone[i]);
    const double difference = distance(fast[i], alone[i]);
    // Near rest rk4's error vanishes too: a floor of 1e-12 of the state's size.
    const double size = std::abs(alone[i].final_state.q1) + std::abs(alone[i].final_state.u1) +
                        std::abs(alone[i].final_state.q2) + std::abs(alone[i].final_state.u2);
    EXPECT_LE(difference, 1e-6 * integrator_error + 1e-12 * (1 + size)) << "case " << i;
    worst = std::max(worst, difference / integrator_error);
    ++compared;
  }
  EXPECT_GT(compared, 100);
  std::cout << "vector sin/cos against libm's: at most " << worst
            << " of rk4's own error (h against h/2) over " << compared << " cases\n";
}

TEST(Sweep, SimdChoicesAreCheckedByName) {
  SweepSettings settings;
  settings.duration = 0.1;
  const SweepPlan plan = sweepGrid({parseSweepAxis("mechanism.spring_stiffness=100:200:2")});
  for (const char* bad : {"avx1024", "", "AVX2", "auto "}) {
    settings.simd = bad;
    try {
      runSweep(baseYaml(), plan, settings);
      ADD_FAILURE() << "accepted simd '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_THROW(parseLaneArch("sse3"), std::invalid_argument);
  EXPECT_EQ(parseLaneArch("scalar"), LaneArch::kScalar);
  EXPECT_TRUE(laneArchAvailable(parseLaneArch("auto")));
}

}  // namespace
}  // namespace kane_sim

// The one thread helper (sweeps, BatchSimulator, batched rates): every item once, whatever the
// thread count; a worker's exception reaches the caller after the others finish.
TEST(Parallel, EveryItemOnceAndAWorkersExceptionReachesTheCaller) {
  for (unsigned threads : {0u, 1u, 2u, 3u, 7u, 64u}) {
    for (std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{5}, std::size_t{1000}}) {
      std::vector<std::atomic<int>> seen(count);
      kane_sim::parallelFor(count, threads, [&](std::size_t k) { ++seen[k]; });
      for (std::size_t k = 0; k < count; ++k) ASSERT_EQ(seen[k], 1) << threads << " " << k;
      std::vector<std::atomic<int>> blocks(count);
      kane_sim::parallelBlocks(static_cast<long>(count), threads, [&](long begin, long end) {
        for (long k = begin; k < end; ++k) ++blocks[k];
      });
      for (std::size_t k = 0; k < count; ++k) ASSERT_EQ(blocks[k], 1) << threads << " " << k;
    }
  }
  std::atomic<int> finished{0};
  EXPECT_THROW(kane_sim::runWorkers(4,
                                    [&](unsigned j) {
                                      if (j == 2) throw std::runtime_error("worker 2");
                                      ++finished;
                                    }),
               std::runtime_error);
  EXPECT_EQ(finished, 3);
}

// The BatchSimulator's pool: every item once in call after call (helpers spinning, sleeping,
// or waking after the call ended), whatever the size; an exception reaches the caller and the
// pool keeps working; destroyed at once after a call (a helper still spinning).
TEST(WorkerPool, EveryItemOnceCallAfterCallAndAnExceptionReachesTheCaller) {
  using std::chrono::microseconds;
  for (unsigned workers : {0u, 1u, 2u, 5u}) {
    for (microseconds spin : {microseconds(0), microseconds(100)}) {
      kane_sim::WorkerPool pool(workers, spin);
      EXPECT_EQ(pool.size(), std::max(workers, 1u));
      for (int call = 0; call < 2000; ++call) {
        const std::size_t count = static_cast<std::size_t>(call % 19);
        std::vector<std::atomic<int>> seen(count);
        pool.forEach(count, [&](std::size_t k) { ++seen[k]; });
        for (std::size_t k = 0; k < count; ++k)
          ASSERT_EQ(seen[k], 1) << workers << " " << call << " " << k;
        if (call % 500 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      EXPECT_THROW(pool.forEach(64,
                                [&](std::size_t k) {
                                  if (k == 3) throw std::runtime_error("item 3");
                                }),
                   std::runtime_error);
      std::vector<std::atomic<int>> after(40);
      pool.forEach(after.size(), [&](std::size_t k) { ++after[k]; });
      for (auto& a : after) EXPECT_EQ(a, 1);
    }
  }
}

// Batched rates are the single state's rates, bit for bit, on one thread and across the cores.
TEST(StateRates, EqualTheSimulatorsOwnRatesAndNameTheFirstNonFiniteRow) {
  const kane_sim::Config config = kane_sim::loadConfigFile(kane_sim::defaultConfigFile()).config;
  kane_sim::Simulator sim(config);
  for (long n : {3L, kane_sim::kParallelRatesFrom + 5}) {
    std::vector<double> states(4 * n), out(4 * n), torque(n);
    for (long i = 0; i < n; ++i) {
      states[4 * i] = 0.001 * i, states[4 * i + 1] = 0.1, states[4 * i + 2] = 1e-4 * i;
      states[4 * i + 3] = -0.2;
      torque[i] = std::sin(0.01 * i);
    }
    ASSERT_EQ(kane_sim::stateRates(sim, states.data(), n, torque.data(), true, out.data()), -1);
    for (long i : {0L, 1L, n / 2, n - 1}) {
      const kane_sim::State s{states[4 * i], states[4 * i + 1], states[4 * i + 2],
                              states[4 * i + 3]};
      const kane_sim::OdeState d = sim.withEquations(
          [&](const auto& equations) { return equations.stateDerivative(s, torque[i]); });
      for (int k = 0; k < 4; ++k) ASSERT_EQ(out[4 * i + k], d[k]) << i << " " << k;
    }
    states[4 * (n - 1) + 2] = 1e300;  // a crank speed beyond any scale
    EXPECT_EQ(kane_sim::stateRates(sim, states.data(), n, torque.data(), true, out.data()), n - 1);
  }
}
