// Torque profiles of the offline tool.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "kane_sim/sim/torque_profile.h"

namespace kane_sim {
namespace {

TEST(TorqueProfile, ConstantStepSine) {
  EXPECT_EQ(TorqueProfile::constant(2.5).at(100.0), 2.5);
  const auto step = TorqueProfile::step(1.0, -1.0, 3.0);
  EXPECT_EQ(step.at(0.999), -1.0);
  EXPECT_EQ(step.at(1.0), 3.0);
  const auto sine = TorqueProfile::sine(2.0, 0.5, 1.0);
  EXPECT_NEAR(sine.at(0.5), 1.0 + 2.0, 1e-12);  // quarter period of 0.5 Hz
  EXPECT_NEAR(sine.at(1.0), 1.0, 1e-12);
}

// A sine whose value overflows somewhere within the longest run is refused by name; the largest
// one that does not is evaluated to finite values all the way.
TEST(TorqueProfile, SinesThatCannotBeEvaluatedAreRefused) {
  EXPECT_THROW(TorqueProfile::sine(1.0, 1e308, 0.0), std::invalid_argument);
  EXPECT_THROW(TorqueProfile::sine(1.0, -1e308, 0.0), std::invalid_argument);
  EXPECT_THROW(TorqueProfile::sine(1e308, 1.0, 1e308), std::invalid_argument);
  const auto fast = TorqueProfile::sine(1.0, 1e300, 0.0);
  for (const double t : {0.0, 1e-3, 1.0, 1e7}) EXPECT_TRUE(std::isfinite(fast.at(t))) << t;
  try {
    TorqueProfile::sine(1.0, 1e308, 0.0);
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sine frequency 1e+308 Hz"), std::string::npos);
  }
}

TEST(TorqueProfile, TableHoldsEachValueFromItsTime) {
  const auto t = TorqueProfile::table({{0.5, 1.0}, {1.0, -2.0}, {1.0, 4.0}, {2.0, 0.0}});
  EXPECT_EQ(t.at(0.0), 0.0);  // before the first entry
  EXPECT_EQ(t.at(0.5), 1.0);
  EXPECT_EQ(t.at(0.99), 1.0);
  EXPECT_EQ(t.at(1.0), 4.0);  // the later of two entries at one time wins
  EXPECT_EQ(t.at(10.0), 0.0);
}

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

void expectCsvError(const std::string& text, const std::string& message) {
  const std::string path = writeFile("profile.csv", text);
  try {
    TorqueProfile::fromCsvFile(path);
    ADD_FAILURE() << "accepted: " << text;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(TorqueProfile, CsvWithHeaderAndComments) {
  const auto p =
      TorqueProfile::fromCsvFile(writeFile("ok.csv", "t,torque\n# ramp\n0,1\n0.5, 2.5\n1e0,-3\n"));
  EXPECT_EQ(p.at(0.25), 1.0);
  EXPECT_EQ(p.at(0.75), 2.5);
  EXPECT_EQ(p.at(2.0), -3.0);
}

// A header is recognised by its content, never by its first character: a first data row with a
// leading blank, after a UTF-8 byte-order mark, or with a non-finite value is data.
TEST(TorqueProfile, FirstDataRowIsNeverTakenForAHeader) {
  for (const char* text : {" 0,20\n0.5,-5\n",
                           "\xEF\xBB\xBF"
                           "0,20\n0.5,-5\n",
                           "\t0 , 20\n0.5,-5\n", "\xEF\xBB\xBFt,torque\n0,20\n0.5,-5\n"}) {
    const auto p = TorqueProfile::fromCsvFile(writeFile("first.csv", text));
    EXPECT_EQ(p.at(0.0), 20.0) << text;
    EXPECT_EQ(p.at(0.6), -5.0) << text;
  }
  expectCsvError("nan,5\n1,2\n", "profile.csv:1 (time): 'nan' is not finite");
  expectCsvError("inf,5\n", "profile.csv:1 (time): 'inf' is not finite");
  expectCsvError("e,5\n", "profile.csv:1 (time): 'e' is not a number");
  // Values below double's normal range are numbers (as --torque 1e-320 is).
  EXPECT_EQ(TorqueProfile::fromCsvFile(writeFile("tiny.csv", "0,1e-320\n")).at(1.0), 1e-320);
}

// pd_controller's ~setpoint_table: the same reader, its values setpoints [rad]. A torque's
// table (its header names torque or M_m) is refused, a setpoint beyond a million turns too, and
// the messages say setpoint.
TEST(TorqueProfile, ASetpointTableIsNotATorquesAndSaysSetpoint) {
  const auto setpoints = [](const std::string& text) {
    return TorqueProfile::fromCsvFile(writeFile("sp.csv", text),
                                      TorqueProfile::TableValue::kSetpoint);
  };
  EXPECT_EQ(setpoints("t,setpoint\n0,0.5\n1,-1\n").at(1.5), -1.0);
  EXPECT_EQ(setpoints("0,0.5\n1,-1\n").at(0.5), 0.5);  // no header: the first two columns
  EXPECT_EQ(setpoints("time,x,setpoint\n0,9,0.5\n").at(0.0), 0.5);
  const std::pair<const char*, const char*> refused[] = {
      {"t,torque\n0,20\n", "sp.csv:1: the header 't,torque' names a torque [N m], not a setpoint"},
      {"t,q1,q2,u1,u2,M_m\n0,0,0,0,0,1\n", "names a torque [N m]"},
      {"0,1e308\n", "sp.csv:1 (setpoint): 1e308 rad is beyond a million turns"},
      {"0,nan\n", "sp.csv:1 (setpoint): 'nan' is not finite"},
      {"0,1,2\n", "expected 't,setpoint'"},
      {"t,setpoint\n", "setpoint CSV '"},
  };
  for (const auto& [text, message] : refused) {
    try {
      setpoints(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  // Read before the mode is known (simulate's flags, Python's from_csv), a table is read and
  // its header remembered: played as torques (effort mode), a setpoint table is refused, and a
  // torque's table, one without a header or one naming both plays; played as setpoints, a
  // torque's table is refused. The pickle a cluster's worker gets keeps it.
  const auto table = [](const std::string& text) {
    return TorqueProfile::fromCsvFile(writeFile("tq.csv", text));
  };
  EXPECT_EQ(table("t,setpoint\n0,0.5\n").at(0.0), 0.5);
  for (const char* text :
       {"t,torque\n0,2\n", "0,2\n", "t,q1,q2,u1,u2,M_m,setpoint\n0,0,0,0,0,3,9\n"})
    EXPECT_NO_THROW(table(text).checkPlaysAs(false)) << text;
  for (const char* text : {"t,setpoint\n0,0.5\n", "0,2\n"})
    EXPECT_NO_THROW(table(text).checkPlaysAs(true)) << text;
  const std::pair<const char*, bool> played_otherwise[] = {
      {"tq.csv:1: the header 't,setpoint' names a setpoint, not a torque [N m]", false},
      {"tq.csv:1: the header 't,torque' names a torque [N m], not a setpoint [rad]", true}};
  for (const auto& [message, setpoints] : played_otherwise) {
    const TorqueProfile read = table(setpoints ? "t,torque\n0,2\n" : "t,setpoint\n0,0.5\n");
    for (const TorqueProfile& p : {read, TorqueProfile::fromParts(read.parts())}) {
      try {
        p.checkPlaysAs(setpoints);
        ADD_FAILURE() << message;
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
      }
    }
  }
}

TEST(TorqueProfile, MalformedCsvNamesLineAndValue) {
  expectCsvError("0,1\n0.5,abc\n", "profile.csv:2 (torque): 'abc' is not a number");
  expectCsvError("0,1\n1,2\n0.5,3\n", "profile.csv:3: time 0.5 goes backwards");
  expectCsvError("0,1\n1;2\n", "profile.csv:2: expected 't,torque'");
  expectCsvError("0,nan\n", "profile.csv:1 (torque): 'nan' is not finite");
  expectCsvError("t,torque\n", "has no rows");
  try {
    TorqueProfile::fromCsvFile("/nonexistent.csv");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'/nonexistent.csv' is not a readable file"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace kane_sim
