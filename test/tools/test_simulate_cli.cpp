// The `simulate` executable, run as a user would: CSV layout, time grid, exit codes.
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_helpers.h"

namespace {

using RunResult = kane_sim::test::CommandResult;

RunResult runSimulate(const std::string& args) {
  return kane_sim::test::runCommand(std::string(KANE_SIM_SIMULATE_EXE) + " " + args);
}

std::vector<std::vector<double>> parseRows(const std::string& csv, std::string* header) {
  return kane_sim::test::parseCsv(csv, header);
}

const std::string kConfig = "--config " + kane_sim::test::configPath("mechanism.yaml");

TEST(SimulateCli, HeaderRowsAndTimeGrid) {
  const RunResult r = runSimulate(kConfig + " --duration 2 --output-rate 50 --torque 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string header;
  const auto rows = parseRows(r.out, &header);
  EXPECT_EQ(header.rfind("t,q1,q2,u1,u2,total_energy", 0), 0u) << header;
  ASSERT_EQ(rows.size(), 101u);  // t = 0, 0.02, ..., 2.0
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_NEAR(rows[i][0], i / 50.0, 1e-12);
    EXPECT_EQ(rows[i].size(), rows[0].size());
  }
  EXPECT_NEAR(rows[0][1], M_PI / 6, 1e-15);  // q1 at t = 0 is the configured q10
  EXPECT_NE(r.err.find("steps/s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("2000 physics steps"), std::string::npos) << r.err;
}

// The driver's events reach stderr once each, whatever the run length: a command over the
// limit, the sliders crossing and rk4 falling behind the crank (50 N m spins it past 50 rad/s
// within 5 s).
TEST(SimulateCli, DriverEventsArePrintedOnceEach) {
  const RunResult r = runSimulate(kConfig + " --duration 5 --output-rate 10 --torque 80");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto count = [&r](const std::string& text) {
    int n = 0;
    for (size_t at = r.err.find(text); at != std::string::npos; at = r.err.find(text, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("exceeds command.torque_limit 50 N m: clamped to 50 N m"), 1) << r.err;
  EXPECT_EQ(count("slider 4 passed through slider 3"), 1) << r.err;
  EXPECT_EQ(count("rk4 at 1000 Hz no longer resolves the motion"), 1) << r.err;
  EXPECT_EQ(count("warning: "), 3) << r.err;
}

TEST(SimulateCli, DefaultOutputRateIs100HzAndCsvFileWorks) {
  const std::string path = ::testing::TempDir() + "/run.csv";
  const RunResult r = runSimulate(kConfig + " --duration 0.5 --integrator dopri5 --csv " + path);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
  std::ifstream file(path);
  const std::string csv((std::istreambuf_iterator<char>(file)), {});
  std::string header;
  EXPECT_EQ(parseRows(csv, &header).size(), 51u);
}

TEST(SimulateCli, BadFlagsExitWithUsage) {
  for (const std::string& args :
       {kConfig, kConfig + " --duration -1", kConfig + " --duration abc",
        kConfig + " --duration 1 --output-rate 0", kConfig + " --duration 1 --output-rate 300",
        kConfig + " --duration 1 --integrator euler", kConfig + " --duration 1 --bogus",
        kConfig + " --duration nan"}) {
    const RunResult r = runSimulate(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("Usage: simulate"), std::string::npos) << args << "\n" << r.err;
  }
}

TEST(SimulateCli, BadConfigExitsOneNamingTheKey) {
  const RunResult missing = runSimulate("--config /nonexistent.yaml --duration 1");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("config '/nonexistent.yaml' is not a readable file (no such file)"),
            std::string::npos)
      << missing.err;

  const std::string path = ::testing::TempDir() + "/bad.yaml";
  std::ifstream in(kane_sim::test::configPath("mechanism.yaml"));
  std::string text((std::istreambuf_iterator<char>(in)), {});
  text.replace(text.find("rod_mass: 1.0"), 13, "rod_mass: -2");
  std::ofstream(path) << text;
  const RunResult bad = runSimulate("--config " + path + " --duration 1");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("mechanism.rod_mass' must be > 0, got -2"), std::string::npos) << bad.err;
}

TEST(SimulateCli, UnwritableOutputExitsFour) {
  const RunResult r = runSimulate(kConfig + " --duration 1 --csv /nonexistent/dir/out.csv");
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_NE(r.err.find("/nonexistent/dir/out.csv"), std::string::npos) << r.err;
  const RunResult bag = runSimulate(kConfig + " --duration 1 --bag /nonexistent/dir/out.bag");
  EXPECT_EQ(bag.exit_code, 4);
  EXPECT_NE(bag.err.find("cannot write --bag '/nonexistent/dir/out.bag'"), std::string::npos)
      << bag.err;
}

TEST(SimulateCli, AbsurdValuesAndBadTorqueProfilesAreUsageErrors) {
  const std::string csv = ::testing::TempDir() + "/backwards.csv";
  std::ofstream(csv) << "t,torque\n0,1\n1,2\n0.5,3\n";
  // A table's header says what its values are; the config's command.mode what they drive.
  const std::string setpoints = ::testing::TempDir() + "/setpoints.csv";
  std::ofstream(setpoints) << "t,setpoint\n0,0.5\n";
  const std::string torques = ::testing::TempDir() + "/torques.csv";
  std::ofstream(torques) << "t,torque\n0,0.5\n";
  std::string servo_yaml;
  {
    std::ifstream in(kane_sim::test::configPath("mechanism.yaml"));
    servo_yaml.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    const std::size_t mode = servo_yaml.find("mode: effort");
    ASSERT_NE(mode, std::string::npos);
    servo_yaml.replace(mode, 12, "mode: position");
  }
  const std::string servo = ::testing::TempDir() + "/position_servo.yaml";
  std::ofstream(servo) << servo_yaml;
  const struct {
    std::string args;
    std::string message;
  } cases[] = {
      {" --duration 1e12", "--duration must be in [0, 1e+07] s"},
      {" --duration 1 --output-rate 1e300", "must divide simulation.physics_rate"},
      {" --duration 1 --torque-csv " + csv, "backwards.csv:4: time 0.5 goes backwards"},
      {" --duration 1 --torque-csv /nonexistent.csv", "'/nonexistent.csv' is not a readable file"},
      // Devices and pipes are refused before a byte is read (/dev/zero once ran to 1 GB).
      {" --duration 1 --torque-csv /dev/zero", "torque CSV '/dev/zero' is not a readable file"},
      {" --duration 1 --sweep-file /dev/zero", "sweep file '/dev/zero' is not a readable file"},
      {" --duration 1 --torque-step 1,2", "--torque-step takes 3 comma-separated numbers"},
      {" --duration 1 --torque-sine 1,x", "--torque-sine: 'x' is not a number"},
      // A sine that cannot be evaluated was every row's torque 0 (the reason only in events).
      {" --duration 1 --torque-sine 10,1e308", "--torque-sine: sine frequency 1e+308 Hz cannot"},
      {" --duration 1 --torque-sine 1e308,1,1e308", "offset + amplitude overflows"},
      {" --duration 1 --torque 1 --torque-sine 1,2", "give at most one of --torque"},
      {" --duration 1 --torque inf", "--torque must be finite"},
      {" --replay x.bag --duration 1", "--replay takes the bag's inputs and times: no --duration"},
      {" --replay x.bag --torque 2", "no --torque"},
      {" --replay x.bag --csv out.csv", "no --csv"},
      {" --replay x.bag --tolerance nan", "--tolerance must be finite"},
      {" --replay x.bag --tolerance -1", "--tolerance must be >= 0"},
      {" --duration 1 --tolerance 1", "--tolerance is for --replay"},
      {" --duration 1 --accept-gaps", "--accept-gaps is for --replay"},
      {"", "the option '--duration' is required"},
      {" --duration 1 --torque-csv " + setpoints,
       "--torque-csv in command.mode effort: " + setpoints +
           ":1: the header 't,setpoint' names a setpoint, not a torque [N m]"},
  };
  for (const auto& c : cases) {
    const RunResult r = runSimulate(kConfig + c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
  }
  // In a servo mode the table is the setpoint's: a torque's is refused, a setpoint's plays.
  const RunResult torque_as_setpoint =
      runSimulate("--config " + servo + " --duration 0.1 --torque-csv " + torques);
  EXPECT_EQ(torque_as_setpoint.exit_code, 2) << torque_as_setpoint.err;
  EXPECT_NE(torque_as_setpoint.err.find("--torque-csv in command.mode position: " + torques +
                                        ":1: the header 't,torque' names a torque [N m], not a "
                                        "setpoint"),
            std::string::npos)
      << torque_as_setpoint.err;
  EXPECT_EQ(
      runSimulate("--config " + servo + " --duration 0.1 --torque-csv " + setpoints).exit_code, 0);
}

// Hostile input never aborts: each case ends with its documented exit code and a message, never
// a signal (exit_code -1) or an uncaught exception (134).
TEST(SimulateCli, HostileInputEndsWithItsExitCode) {
  const std::string dir = ::testing::TempDir();
  std::ifstream in(kane_sim::test::configPath("mechanism.yaml"));
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  const auto variant = [&](const std::string& name, const std::string& extra_first) {
    std::ofstream(dir + "/" + name) << extra_first << text;
    return "--config " + dir + "/" + name;
  };
  const struct {
    std::string args;
    int exit_code;
    std::string message;
  } cases[] = {
      {variant("complex_key.yaml", "? [a, b]\n: 1\n") + " --duration 1", 1, "not a plain name"},
      {"--config /etc --duration 1", 1, "not a readable file"},
      {"--config /dev/zero --duration 1", 1, "config '/dev/zero' is not a readable file"},
      // A config past 1 MiB is refused by its size (a 36 MB one took 26 s and 1.4 GB to fail).
      {variant("huge.yaml", std::string(2 << 20, '#') + "\n") + " --duration 1", 1,
       "more than the 1048576 a config may have"},
      {variant("dup.yaml", "command: {}\n") + " --duration 1", 1, "'command' appears twice"},
      {kConfig + " --duration 1 --bag /dev/full", 4, "--bag '/dev/full'"},
      {kConfig + " --duration 1 --output-rate 1e-300", 2, "must divide"},
      {kConfig + " --duration 0.015", 2, "not a whole number of output periods"},
      {kConfig + " --duration 1 --integrator euler", 2, "--integrator must be rk4 or dopri5"},
      {kConfig + " --duration 1 --csv " + kane_sim::test::configPath("mechanism.yaml"), 2,
       "must not name the --config file"},
      {kConfig + " --duration 1 --csv " + dir + "/same --bag " + dir + "/same", 2,
       "must name different files"},
      {kConfig + " --duration 1 --bag ''", 2, "--bag needs a file name"},
      {kConfig + " --duration 1 --torque-step 1,2,3,", 2, "ends with a comma"},
  };
  for (const auto& c : cases) {
    const RunResult r = runSimulate(c.args);
    EXPECT_EQ(r.exit_code, c.exit_code) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
  }
  // A file-size limit mid-run (a full disk): exit 4 for the CSV and the bag alike.
  for (const std::string& output : {" --csv " + dir + "/big.csv", " --bag " + dir + "/big.bag"}) {
    const RunResult r =
        kane_sim::test::runCommand("ulimit -f 200; " + std::string(KANE_SIM_SIMULATE_EXE) + " " +
                                   kConfig + " --duration 300" + output);
    EXPECT_EQ(r.exit_code, 4) << output << "\n" << r.err;
    EXPECT_NE(r.err.find("disk full?"), std::string::npos) << output << "\n" << r.err;
  }
}

// --sweep: one row per case with the swept values, and a row equal to the final row of the same
// case run alone (a config file with that value), to the last digit printed.
TEST(SimulateCli, SweepRowsMatchSingleRuns) {
  const std::string csv = ::testing::TempDir() + "/sweep.csv";
  const RunResult r = runSimulate(kConfig + " --duration 1 --torque 3 --jobs 2 --csv " + csv +
                                  " --sweep mechanism.slider4_mass=0.4:1.2:3 --sweep "
                                  "damping.crank_joint=0:0.5:2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("swept 6 of 6 cases (0 not ok)"), std::string::npos) << r.err;
  std::ifstream in(csv);
  std::stringstream text;
  text << in.rdbuf();
  std::string header;
  std::istringstream lines(text.str());
  std::getline(lines, header);
  EXPECT_EQ(
      header.rfind("case,mechanism.slider4_mass,damping.crank_joint,status,t,q1,q2,u1,u2,", 0), 0u)
      << header;
  std::vector<std::string> rows;
  for (std::string line; std::getline(lines, line);) rows.push_back(line);
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[3].rfind("3,0.8,0.5,ok,1,", 0), 0u) << rows[3];

  // Case 3 alone: slider4_mass 0.8 (the shipped value) with crank damping 0.5.
  std::ifstream shipped(kane_sim::test::configPath("mechanism.yaml"));
  std::stringstream yaml;
  yaml << shipped.rdbuf();
  std::string config = yaml.str();
  const std::string from = "  crank_joint: 0.0";
  ASSERT_NE(config.find(from), std::string::npos);
  config.replace(config.find(from), from.size(), "  crank_joint: 0.5");
  const std::string path = ::testing::TempDir() + "/damped.yaml";
  std::ofstream(path) << config;
  const RunResult single =
      runSimulate("--config " + path + " --duration 1 --torque 3 --output-rate 1");
  ASSERT_EQ(single.exit_code, 0) << single.err;
  std::string single_header;
  const auto single_rows = parseRows(single.out, &single_header);
  ASSERT_EQ(single_rows.size(), 2u);
  std::vector<double> swept;
  std::istringstream fields(rows[3]);
  for (std::string field; std::getline(fields, field, ',');)
    swept.push_back(field == "ok" ? 0.0 : std::stod(field));
  // Columns: case, 2 keys, status, t, q1, q2, u1, u2 (CSV of the single run: t,q1,q2,u1,u2).
  for (int c = 0; c < 5; ++c) EXPECT_NEAR(swept[4 + c], single_rows[1][c], 1e-12) << c;
}

// KANE_SIM_SIMD_MAX caps the instruction sets as a narrower CPU would: auto picks the cap, a
// wider set is refused naming the cap, and the capped sweep's rows equal the uncapped ones bit for
// bit (every lane is its single run's arithmetic). A value naming no set stops the run, named.
TEST(SimulateCli, SimdCapActsAsANarrowerCpu) {
  const std::string sweep = kConfig +
                            " --duration 0.5 --torque 2 --output-rate 2 --sweep "
                            "mechanism.slider4_mass=0.4:1.2:5";
  const auto withoutWallTime = [](const std::string& csv) {  // each line but its last column
    std::string out;
    std::istringstream lines(csv);
    for (std::string line; std::getline(lines, line);)
      out += line.substr(0, line.rfind(',')) + "\n";
    return out;
  };
  const RunResult uncapped = runSimulate(sweep + " --simd scalar");
  ASSERT_EQ(uncapped.exit_code, 0) << uncapped.err;
  for (const std::string set : {"scalar", "sse2"}) {
    const RunResult capped = kane_sim::test::runCommand("KANE_SIM_SIMD_MAX=" + set + " " +
                                                        KANE_SIM_SIMULATE_EXE + " " + sweep);
    ASSERT_EQ(capped.exit_code, 0) << set << ": " << capped.err;
    EXPECT_EQ(withoutWallTime(capped.out), withoutWallTime(uncapped.out)) << set;
  }
  RunResult r = kane_sim::test::runCommand(std::string("KANE_SIM_SIMD_MAX=scalar ") +
                                           KANE_SIM_SIMULATE_EXE + " " + sweep + " --simd sse2");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("simd 'sse2': KANE_SIM_SIMD_MAX=scalar excludes sse2"), std::string::npos)
      << r.err;
  // A bad value is named whatever the run (a sweep on lanes or not, a single run), on one line:
  // the mistake is not in the flags, so no usage text follows.
  for (const std::string hostile : {"avx9", "AVX2", "' '", "auto"})
    for (const std::string& run :
         {sweep, sweep + " --simd avx2", sweep + " --simd off", kConfig + " --duration 0.1"}) {
      r = kane_sim::test::runCommand("KANE_SIM_SIMD_MAX=" + hostile + " " + KANE_SIM_SIMULATE_EXE +
                                     " " + run);
      EXPECT_EQ(r.exit_code, 2) << hostile << " " << run << ": " << r.err;
      EXPECT_EQ(r.err.rfind("error: environment variable KANE_SIM_SIMD_MAX '", 0), 0u)
          << hostile << " " << run << ": " << r.err;
      EXPECT_EQ(r.err.find("Usage"), std::string::npos) << r.err;
    }
}

TEST(SimulateCli, SweepRefusesTyposAndBagsNamingThem) {
  RunResult r = runSimulate(kConfig + " --duration 1 --sweep mechanism.spring=1:2:2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("'mechanism.spring' is not a config key"), std::string::npos) << r.err;
  r = runSimulate(kConfig + " --duration 1 --sweep mechanism.gravity=1:2 ");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("START:STOP:COUNT"), std::string::npos) << r.err;
  r = runSimulate(kConfig + " --duration 1 --sweep mechanism.gravity=1:2:2 --bag /tmp/x.bag");
  EXPECT_EQ(r.exit_code, 2);
  r = runSimulate(kConfig + " --duration 1 --jobs 2");
  EXPECT_EQ(r.exit_code, 2);
}

// Round three of hostile sweeps: a typo'd or capitalised section ran the base config three
// times with exit 0; a BOM broke the header; a formula-like header cell was accepted; a refused
// value in the first case exited 1 without rows while the same range reversed gave rows; a range
// to +-1e308 overflowed to NaN; --jobs -1 became 4294967295 threads.
TEST(SimulateCli, SweepHostileInput) {
  const std::string dir = ::testing::TempDir();
  for (const std::string key : {"mechanizm.spring_stiffness", "Mechanism.spring_stiffness"}) {
    const RunResult r = runSimulate(kConfig + " --duration 0.1 --sweep " + key + "=100:400:3");
    EXPECT_EQ(r.exit_code, 2) << key << r.err;
    EXPECT_NE(r.err.find("'" + key + "' is not a config key"), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("ok"), std::string::npos) << "nothing ran: " << r.out;
  }
  std::ofstream(dir + "/bom.csv") << "\xEF\xBB\xBFmechanism.spring_stiffness\n100\n200\n";
  RunResult r = runSimulate(kConfig + " --duration 0.1 --sweep-file " + dir + "/bom.csv");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("case,mechanism.spring_stiffness,status", 0), 0u) << r.out;
  for (const std::string cell : {"=cmd.x", "+a.b", "-a.b", "@a.b", "=HYPERLINK(a.b)"}) {
    std::ofstream(dir + "/formula.csv") << cell << "\n1\n";
    r = runSimulate(kConfig + " --duration 0.1 --sweep-file " + dir + "/formula.csv");
    EXPECT_EQ(r.exit_code, 2) << cell;
    EXPECT_NE(r.err.find("spreadsheet formula"), std::string::npos) << cell << r.err;
  }
  for (const std::string range : {"-1:1:3", "1:-1:3"}) {
    r = runSimulate(kConfig + " --duration 0.1 --sweep mechanism.rod_mass=" + range);
    EXPECT_EQ(r.exit_code, 3) << range << r.err;
    std::string header;
    std::istringstream lines(r.out);
    std::string line;
    int refused = 0, ok = 0, rows = 0;
    std::getline(lines, header);
    while (std::getline(lines, line)) {
      ++rows;
      refused += line.find(",config_refused,") != std::string::npos;
      ok += line.find(",ok,") != std::string::npos;
    }
    EXPECT_EQ(rows, 3) << range << r.out;
    EXPECT_EQ(refused, 2) << range;
    EXPECT_EQ(ok, 1) << range;
  }
  r = runSimulate(kConfig + " --duration 0.1 --sweep mechanism.gravity=-1e308:1e308:3");
  EXPECT_NE(r.out.find("\n0,-1e+308,config_refused"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n1,0,ok"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n2,1e+308,config_refused"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
  for (const std::string jobs : {"-1", "0", "100000", "abc"}) {
    r = runSimulate(kConfig + " --duration 0.1 --sweep mechanism.gravity=1:2:2 --jobs " + jobs);
    EXPECT_EQ(r.exit_code, 2) << jobs << r.err;
    EXPECT_NE(r.err.find("jobs"), std::string::npos) << jobs << r.err;
  }
}

// Runs `args` in the background and sends SIGINT once the run has shown it is under way: its
// staged FILE.partial holds at least `lines` lines (a header and finished rows). The wait is
// bounded (120 s, then the signal anyway) but does not assume the machine's speed: the work asked
// for must outlast any machine. Returns what it printed and its exit code; `before` is the --csv
// file's content read while it runs, just before the signal.
RunResult interruptOnceUnderWay(const std::string& args, const std::string& csv, int lines,
                                std::string* before) {
  const std::string partial = csv + ".partial";
  const std::string command = "( " + std::string(KANE_SIM_SIMULATE_EXE) + " " + args +
                              " & pid=$!; i=0; while [ $i -lt 12000 ] && "
                              "[ \"$(cat " +
                              partial + " 2>/dev/null | wc -l)\" -lt " + std::to_string(lines) +
                              " ]; do sleep 0.01; i=$((i+1)); done; cat " + csv + " > " + csv +
                              ".before; kill -INT $pid; wait $pid )";
  const RunResult r = kane_sim::test::runCommand(command);
  std::ifstream in(csv + ".before");
  before->assign(std::istreambuf_iterator<char>(in), {});
  return r;
}

// An interrupted run keeps what it computed: SIGINT once a long sweep has finished its first
// cases keeps every finished case (rows in case order, complete lines), exit 130; the CSV it
// replaces is not destroyed while the run goes on. The same for a single run's --csv. The work
// (10^5 cases of 200 s; a run of 10^7 s) takes minutes even on the fastest lanes, so the signal
// always comes first.
TEST(SimulateCli, InterruptedRunsKeepWhatTheyComputed) {
  const std::string dir = ::testing::TempDir();
  const std::string csv = dir + "/interrupted.csv";
  constexpr size_t kCases = 100000;
  std::ofstream(csv) << "the previous results\n";
  std::string before;
  RunResult r = interruptOnceUnderWay(kConfig +
                                          " --duration 200 --jobs 1 --sweep "
                                          "mechanism.spring_stiffness=100:400:" +
                                          std::to_string(kCases) + " --csv " + csv,
                                      csv, 3, &before);
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_EQ(before, "the previous results\n") << "replaced before the run ended";
  EXPECT_NE(r.err.find("interrupted: kept the"), std::string::npos) << r.err;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("case,mechanism.spring_stiffness,status", 0), 0u) << line;
  size_t rows = 0;
  while (std::getline(in, line)) {
    EXPECT_EQ(line.rfind(std::to_string(rows) + ",", 0), 0u) << "case order: " << line;
    EXPECT_NE(line.find(",ok,"), std::string::npos) << line;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 16) << "a whole row: " << line;
    ++rows;
  }
  EXPECT_GE(rows, 2u) << "the rows seen before the signal are kept";
  EXPECT_LT(rows, kCases);

  std::ofstream(csv) << "the previous results\n";
  r = interruptOnceUnderWay(kConfig + " --duration 10000000 --output-rate 10 --csv " + csv, csv,
                            102, &before);
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_EQ(before, "the previous results\n");
  EXPECT_NE(r.err.find("interrupted at t = "), std::string::npos) << r.err;
  std::ifstream single(csv);
  const std::string text((std::istreambuf_iterator<char>(single)), {});
  std::string header;
  const auto parsed = parseRows(text, &header);
  ASSERT_GT(parsed.size(), 100u);
  for (size_t i = 0; i < parsed.size(); ++i) EXPECT_NEAR(parsed[i][0], i / 10.0, 1e-9);
  EXPECT_FALSE(std::ifstream(csv + ".partial").good()) << "renamed into place";
}

// Long work shows its progress on a terminal (util-linux's `script` gives simulate one): the
// percentage of sim time or cases, rewritten in place and erased at the end; without a terminal
// (a pipe, as here and in every log) not a byte of it. The first update draws at once, so even a
// machine that finishes in an instant shows one line.
TEST(SimulateCli, ProgressOnATerminalOnly) {
  if (std::system("command -v script >/dev/null 2>&1") != 0) GTEST_SKIP() << "needs script";
  for (const std::string args :
       {" --duration 2000 --output-rate 1", " --duration 1 --sweep mechanism.gravity=1:9:40"}) {
    const std::string what = args.find("--sweep") == std::string::npos ? "simulate: " : "sweep: ";
    const RunResult tty =
        kane_sim::test::runCommand("script -qec '" + std::string(KANE_SIM_SIMULATE_EXE) + " " +
                                   kConfig + args + " >/dev/null' /dev/null");
    EXPECT_EQ(tty.exit_code, 0) << tty.out << tty.err;
    EXPECT_NE(tty.out.find("\r\033[K" + what), std::string::npos) << args << tty.out;
    EXPECT_NE(tty.out.find(" %"), std::string::npos) << tty.out;
    // erased before the summary line
    EXPECT_NE(tty.out.find("\r\033[K" + std::string(what == "sweep: " ? "swept" : "simulated")),
              std::string::npos)
        << tty.out;
    const RunResult piped = runSimulate(kConfig + args);
    EXPECT_EQ(piped.exit_code, 0) << piped.err;
    EXPECT_EQ(piped.err.find('\r'), std::string::npos) << piped.err;
    EXPECT_EQ(piped.err.find(what), std::string::npos) << piped.err;
  }
}

// No --config: the package's config/mechanism.yaml, said in one line (it exited 2 before).
TEST(SimulateCli, WithoutConfigRunsThePackagesDefault) {
  const RunResult r = runSimulate("--duration 0.1");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("no --config given: using the package's default"), std::string::npos)
      << r.err;
  std::string header;
  EXPECT_EQ(parseRows(r.out, &header).size(), 11u);
}

// When the system refuses threads (a process limit), a sweep runs on those it got and says so,
// instead of aborting (it ended with SIGABRT, exit 134). Needs root to run as an unprivileged user
// whose process limit applies (root's does not).
TEST(SimulateCli, SweepSurvivesRefusedThreads) {
  if (geteuid() != 0 || std::system("command -v runuser >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "needs root and runuser";
  const std::string config = ::testing::TempDir() + "/threads.yaml";
  std::ifstream in(kane_sim::test::configPath("mechanism.yaml"));
  std::ofstream(config) << in.rdbuf();
  kane_sim::test::runCommand("chmod 644 " + config);
  // One process allowed for `nobody`: simulate itself; every thread it asks for is refused
  // (--simd off: one case per task, so the sweep asks for four threads).
  const RunResult r = kane_sim::test::runCommand(
      "runuser -u nobody -- bash -c 'ulimit -u 1; exec " + std::string(KANE_SIM_SIMULATE_EXE) +
      " --config " + config +
      " --duration 0.1 --jobs 4 --simd off --sweep mechanism.gravity=1:9:4'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("sweep threads"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("swept 4 of 4 cases (0 not ok)"), std::string::npos) << r.err;
}

}  // namespace
