// Torque command handling: rejection of non-finite values, clamping, timeout, reset.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "kane_sim/sim/torque_command.h"

namespace kane_sim {
namespace {

CommandSettings settings(double limit, double timeout) {
  CommandSettings s;
  s.torque_limit = limit;
  s.timeout = timeout;
  return s;
}

TEST(TorqueCommand, NoCommandMeansZeroTorque) {
  TorqueCommand c(settings(50, 0.5));
  bool timed_out = true;
  EXPECT_EQ(c.applied(10.0, &timed_out), 0.0);
  EXPECT_FALSE(timed_out);  // nothing to time out: no warning before the first command
}

TEST(TorqueCommand, NonFiniteIsRejectedAndLastGoodKept) {
  TorqueCommand c(settings(50, 0));
  std::string msg;
  ASSERT_EQ(c.receive(5.0, 0.0, &msg), TorqueCommand::Verdict::kAccepted);
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()}) {
    EXPECT_EQ(c.receive(bad, 0.1, &msg), TorqueCommand::Verdict::kRejected);
    EXPECT_NE(msg.find("not finite"), std::string::npos) << msg;
    EXPECT_NE(msg.find("ignored, applying 5 N m"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("-nan"), std::string::npos) << msg;
    bool timed_out;
    EXPECT_EQ(c.applied(0.2, &timed_out), 5.0);
    EXPECT_EQ(c.commanded(), 5.0);
  }
}

// After the timeout 0 N m is applied: a NaN then says so (it said "still applying 3 N m").
TEST(TorqueCommand, NonFiniteAfterTheTimeoutSaysZeroIsApplied) {
  TorqueCommand c(settings(50, 0.5));
  std::string msg;
  ASSERT_EQ(c.receive(3.0, 0.0, &msg), TorqueCommand::Verdict::kAccepted);
  bool timed_out = false;
  EXPECT_EQ(c.applied(1.0, &timed_out), 0.0);
  EXPECT_EQ(c.receive(-std::nan(""), 1.0, &msg), TorqueCommand::Verdict::kRejected);
  EXPECT_NE(msg.find("torque_command nan N m is not finite: ignored, applying 0 N m (the last "
                     "command timed out)"),
            std::string::npos)
      << msg;
  // Lapsed but not yet noticed by applied(): the same answer.
  TorqueCommand d(settings(50, 0.5));
  ASSERT_EQ(d.receive(3.0, 0.0, &msg), TorqueCommand::Verdict::kAccepted);
  d.receive(std::nan(""), 0.7, &msg);
  EXPECT_NE(msg.find("applying 0 N m"), std::string::npos) << msg;
}

TEST(TorqueCommand, OutOfRangeIsClampedBothWays) {
  TorqueCommand c(settings(50, 0));
  std::string msg;
  bool timed_out;
  EXPECT_EQ(c.receive(1e300, 0, &msg), TorqueCommand::Verdict::kClamped);
  EXPECT_NE(msg.find("command.torque_limit 50"), std::string::npos) << msg;
  EXPECT_EQ(c.applied(0, &timed_out), 50.0);
  EXPECT_EQ(c.commanded(), 1e300);
  EXPECT_EQ(c.receive(-80, 0, &msg), TorqueCommand::Verdict::kClamped);
  EXPECT_EQ(c.applied(0, &timed_out), -50.0);
}

TEST(TorqueCommand, TinyAndSignedZeroValuesPassUnchanged) {
  TorqueCommand c(settings(50, 0));
  std::string msg;
  bool timed_out;
  EXPECT_EQ(c.receive(-0.0, 0, &msg), TorqueCommand::Verdict::kAccepted);
  EXPECT_EQ(c.applied(0, &timed_out), 0.0);
  const double denormal = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(c.receive(denormal, 0, &msg), TorqueCommand::Verdict::kAccepted);
  EXPECT_EQ(c.applied(0, &timed_out), denormal);
}

TEST(TorqueCommand, TimeoutZeroesOnceAndNextCommandResumes) {
  TorqueCommand c(settings(50, 0.5));
  std::string msg;
  bool timed_out;
  c.receive(7.0, 1.0, &msg);
  EXPECT_EQ(c.applied(1.5, &timed_out), 7.0);  // exactly at the timeout: still on
  EXPECT_FALSE(timed_out);
  EXPECT_EQ(c.applied(1.5001, &timed_out), 0.0);
  EXPECT_TRUE(timed_out);
  EXPECT_EQ(c.applied(2.0, &timed_out), 0.0);
  EXPECT_FALSE(timed_out);  // reported once
  c.receive(3.0, 2.1, &msg);
  EXPECT_EQ(c.applied(2.2, &timed_out), 3.0);
}

TEST(TorqueCommand, ZeroTimeoutDisablesIt) {
  TorqueCommand c(settings(50, 0.0));
  std::string msg;
  bool timed_out;
  c.receive(7.0, 0.0, &msg);
  EXPECT_EQ(c.applied(1e6, &timed_out), 7.0);
}

TEST(TorqueCommand, ResetForgetsTheCommand) {
  TorqueCommand c(settings(50, 0.5));
  std::string msg;
  bool timed_out;
  c.receive(7.0, 0.0, &msg);
  c.reset();
  EXPECT_EQ(c.applied(0.1, &timed_out), 0.0);
  EXPECT_EQ(c.commanded(), 0.0);
}

}  // namespace
}  // namespace kane_sim
