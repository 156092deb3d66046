// Bad and hostile input to a running sim (test/node/robustness.test): odd values, several
// publishers at once, a publisher that dies mid-command, services while commands stream,
// and a crank driven at the torque limit until the sliders pass through each other.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <set>
#include <thread>

#include <gtest/gtest.h>
#include <rosgraph_msgs/Log.h>
#include <std_msgs/Float64.h>
#include <std_srvs/Empty.h>
#include <std_srvs/Trigger.h>

#include "kane_sim/MechanismState.h"
#include "node_test_utils.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

class Robustness : public test::SimNodeTest {};

using test::Recorder;

using test::send;

bool allFinite(const MechanismState& m) {
  for (double v : {m.q[0], m.q[1], m.u[0], m.u[1], m.u_dot[0], m.u_dot[1], m.applied_torque,
                   m.active_forces[0], m.active_forces[1], m.total_energy, m.motor_work})
    if (!std::isfinite(v)) return false;
  return true;
}

TEST_F(Robustness, SignedZeroAndDenormalCommandsPassThrough) {
  send(torque_, 1.0);
  ASSERT_TRUE(test::waitFor([&] { return state_.last().applied_torque == 1.0; }, 2.0));
  send(torque_, -0.0);
  ASSERT_TRUE(test::waitFor([&] { return state_.last().applied_torque == 0.0; }, 2.0));
  const double denormal = std::numeric_limits<double>::denorm_min();
  send(torque_, denormal);
  ASSERT_TRUE(test::waitFor([&] { return state_.last().applied_torque == denormal; }, 2.0));
  for (const auto& m : state_.messages()) EXPECT_TRUE(allFinite(m));
}

// Three publishers at 1 kHz each with different values: every applied torque is one of them,
// and the node keeps publishing at its rate.
TEST_F(Robustness, SeveralPublishersAtOnce) {
  ros::NodeHandle nh;
  Recorder<MechanismState> state(nh, "mechanism_state");
  std::vector<ros::Publisher> pubs;
  for (int i = 0; i < 3; ++i)
    pubs.push_back(test::connectedPublisher<std_msgs::Float64>(nh, "torque_command"));
  ASSERT_TRUE(state.waitForCount(1, 15.0));
  state.clear();
  const double values[] = {1.5, -2.5, 3.5};
  std::atomic<bool> stop{false};
  std::vector<std::thread> threads;
  for (int i = 0; i < 3; ++i)
    threads.emplace_back([&, i] {
      while (!stop) {
        send(pubs[i], values[i]);
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    });
  test::sleepWall(1.0);
  stop = true;
  for (auto& t : threads) t.join();
  const auto msgs = state.messages();
  EXPECT_NEAR(msgs.size(), 100.0, 15.0) << "publish rate under a 3 kHz command load";
  std::set<double> seen;
  for (const auto& m : msgs) {
    EXPECT_TRUE(allFinite(m));
    if (m.applied_torque != 0.0) {
      EXPECT_TRUE(m.applied_torque == 1.5 || m.applied_torque == -2.5 || m.applied_torque == 3.5)
          << m.applied_torque;
      seen.insert(m.applied_torque);
    }
  }
  EXPECT_GE(seen.size(), 2u) << "commands from several publishers were applied";
}

// A commander process streams 5 N m and is killed with SIGKILL: after command.timeout the
// torque goes to 0.
TEST_F(Robustness, TorquePublisherDiesMidCommand) {
  ros::NodeHandle nh;
  Recorder<MechanismState> state(nh, "mechanism_state");
  ASSERT_TRUE(state.waitForCount(1, 15.0));
  const pid_t child = fork();
  if (child == 0) {
    execlp("rostopic", "rostopic", "pub", "-r", "50", "torque_command", "std_msgs/Float64",
           "data: 5.0", static_cast<char*>(nullptr));
    _exit(127);
  }
  ASSERT_GT(child, 0);
  const bool applied = test::waitFor([&] { return state.last().applied_torque == 5.0; }, 15.0);
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  ASSERT_TRUE(applied) << "the commander never got through";
  const double killed_at = state.last().sim_time;
  ASSERT_TRUE(test::waitFor([&] { return state.last().applied_torque == 0.0; }, 3.0));
  EXPECT_LT(state.last().sim_time - killed_at, 0.5 + 0.3) << "timeout 0.5 s plus delivery slack";
}

// pause / step / unpause / reset while commands stream at 1 kHz: between consecutive states
// q moves by at most |u| dt (plus the change of u over dt), except across the reset itself.
TEST_F(Robustness, ServicesWhileCommandsStream) {
  ASSERT_TRUE(ros::service::waitForService("kane_sim/reset", ros::Duration(10)));
  std::atomic<bool> stop{false};
  std::thread streamer([&] {
    for (int i = 0; !stop; ++i) {
      send(torque_, 4.0 * std::sin(i * 0.01));
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  // An ASSERT below returns early: the streamer is stopped and joined on every way out, so the
  // failure is reported instead of std::terminate on a joinable thread.
  struct StopAndJoin {
    std::atomic<bool>& stop;
    std::thread& thread;
    ~StopAndJoin() {
      stop = true;
      if (thread.joinable()) thread.join();
    }
  } stop_and_join{stop, streamer};
  std_srvs::Empty empty;
  std_srvs::Trigger step;
  state_.clear();
  for (int round = 0; round < 3; ++round) {
    test::sleepWall(0.2);
    ASSERT_TRUE(ros::service::call("kane_sim/pause", empty));
    for (int i = 0; i < 5; ++i) {
      ASSERT_TRUE(ros::service::call("kane_sim/step", step));
      EXPECT_TRUE(step.response.success) << step.response.message;
    }
    ASSERT_TRUE(ros::service::call("kane_sim/unpause", empty));
    test::sleepWall(0.2);
    if (round == 1) {
      ASSERT_TRUE(ros::service::call("kane_sim/reset", empty));
    }
  }
  stop = true;
  streamer.join();
  const auto msgs = state_.messages();
  const Config c = test::defaultConfig();
  int resets = 0;
  for (size_t i = 1; i < msgs.size(); ++i) {
    const auto& a = msgs[i - 1];
    const auto& b = msgs[i];
    EXPECT_TRUE(allFinite(b));
    EXPECT_GE(b.sim_time, a.sim_time);
    if (b.motor_work == 0.0 && b.q[0] == c.initial_state.q1 && b.q[1] == c.initial_state.q2) {
      ++resets;
      continue;
    }
    const double dt = b.sim_time - a.sim_time;
    const double bound1 = (std::abs(a.u[0]) + std::abs(b.u[0])) * dt + 1e-9;
    const double bound2 = (std::abs(a.u[1]) + std::abs(b.u[1])) * dt + 1e-9;
    EXPECT_LE(std::abs(b.q[0] - a.q[0]), bound1 + 0.5 * 200 * dt * dt) << "t = " << b.sim_time;
    EXPECT_LE(std::abs(b.q[1] - a.q[1]), bound2 + 0.5 * 200 * dt * dt) << "t = " << b.sim_time;
  }
  EXPECT_GE(resets, 1);
}

// At the torque limit the crank spins up and pulls slider 3 through slider 4's path: the state
// stays finite, the crossing is counted in mechanism_state and logged exactly once.
TEST_F(Robustness, DrivenHardTheSlidersCrossAndItIsReportedOnce) {
  Recorder<rosgraph_msgs::Log> rosout(nh_, "/rosout");  // the node's own log stream
  ASSERT_TRUE(test::waitFor([&] { return rosout.connected(); }, 10.0));
  test::sleepWall(0.5);  // connections to every /rosout publisher, the sim's included
  std_srvs::Empty empty;
  ASSERT_TRUE(ros::service::call("kane_sim/reset", empty));
  for (int i = 0; i < 300 && state_.last().slider_crossings < 2; ++i) {
    send(torque_, 1e9);  // clamped to the limit
    test::sleepWall(0.01);
  }
  const MechanismState last = state_.last();
  EXPECT_GE(last.slider_crossings, 2u);
  EXPECT_EQ(last.applied_torque, 50.0);
  for (const auto& m : state_.messages()) EXPECT_TRUE(allFinite(m));
  test::sleepWall(0.5);
  int reports = 0;
  for (const auto& log : rosout.messages())
    if (log.msg.find("passed through slider 3") != std::string::npos) ++reports;
  EXPECT_EQ(reports, 1);
}

}  // namespace
}  // namespace kane_sim
