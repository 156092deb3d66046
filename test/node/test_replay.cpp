// `simulate --replay` of a bag recorded from the node (test/node/replay.test): the node logs every
// input with its physics tick on ~input_log; the replay feeds them to the same driver and must
// find every recorded mechanism_state again, bit for bit. Without one of the inputs it must not.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <std_srvs/Empty.h>
#include <yaml-cpp/yaml.h>

#include "kane_sim/Checkpoint.h"
#include "kane_sim/InputLog.h"
#include "kane_sim/SetState.h"
#include "kane_sim/StepWithCommand.h"
#include "kane_sim/ros/param_yaml.h"
#include "node_test_utils.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

class Replay : public test::SimNodeTest {};

using test::Recorder;
using test::send;

// A bag as rosbag record writes it: each message at its own stamp (sim time in /clock mode).
void writeBag(const std::string& path, const std::vector<MechanismState>& states,
              const std::vector<InputLog>& inputs, std::size_t leave_out = SIZE_MAX,
              const std::vector<Checkpoint>& checkpoints = {}) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  for (const Checkpoint& c : checkpoints) bag.write("/kane_sim/checkpoint", c.header.stamp, c);
  for (const MechanismState& m : states) bag.write("/mechanism_state", m.header.stamp, m);
  for (std::size_t i = 0; i < inputs.size(); ++i)
    if (i != leave_out) bag.write("/kane_sim/input_log", inputs[i].header.stamp, inputs[i]);
}

TEST_F(Replay, ARecordedRunReplaysBitForBit) {
  Recorder<InputLog> inputs(nh_, "kane_sim/input_log");
  Recorder<Checkpoint> checkpoints(nh_, "kane_sim/checkpoint");
  ASSERT_TRUE(test::waitFor([&] { return inputs.connected(); }, 10.0));
  ASSERT_TRUE(checkpoints.waitForCount(1, 10.0));  // latched: the one at start
  state_.clear();
  // Drive it as a user would: commands at whatever wall times, a refused one, the services.
  send(torque_, 5.0);
  test::sleepWall(0.3);
  send(torque_, -3.0);
  send(torque_, std::nan(""));
  test::sleepWall(0.2);
  SetState set_state;
  set_state.request.q1 = 1.0;
  set_state.request.spring_at_rest = true;
  ASSERT_TRUE(ros::service::call("kane_sim/set_state", set_state));
  ASSERT_TRUE(set_state.response.success);
  send(torque_, 8.0);
  test::sleepWall(0.3);
  // A reconfiguration mid-run: replayed from the checkpoint it publishes (with its config).
  ASSERT_EQ(test::reconfigure("spring_stiffness", 300.0), 300.0);
  test::sleepWall(0.2);
  std_srvs::Empty empty;
  ASSERT_TRUE(ros::service::call("kane_sim/reset", empty));
  send(torque_, 60.0);  // clamped to 50
  test::sleepWall(0.2);
  ASSERT_TRUE(ros::service::call("kane_sim/pause", empty));
  StepWithCommand step;
  step.request.torque = 2.0;
  step.request.steps = 700;  // past half the command timeout: the held torque is re-sent
  ASSERT_TRUE(ros::service::call("kane_sim/step_with_command", step));
  ASSERT_TRUE(step.response.success);
  ASSERT_TRUE(ros::service::call("kane_sim/unpause", empty));
  test::sleepWall(1.0);  // the command times out (0.5 s): part of the run too
  ASSERT_TRUE(ros::service::call("kane_sim/pause", empty));
  test::sleepWall(0.3);  // the last messages in

  const std::vector<InputLog> logged = inputs.messages();
  ASSERT_GE(logged.size(), 9u);  // 6 torques, set_state, reset, >= 2 from step_with_command
  const std::string dir = ::testing::TempDir();
  const std::string bag = dir + "/replay_test.bag", cut = dir + "/replay_cut.bag";
  const std::vector<Checkpoint> recorded = checkpoints.messages();
  writeBag(bag, state_.messages(), logged, SIZE_MAX, recorded);
  writeBag(cut, state_.messages(), logged, 0);  // without the first command
  XmlRpc::XmlRpcValue params;
  ASSERT_TRUE(ros::param::get("/kane_sim", params));
  const std::string config = dir + "/replay_config.yaml";
  std::ofstream(config) << yamlFromXmlRpc(params);

  const std::string simulate = std::string(KANE_SIM_SIMULATE_EXE) + " --config " + config;
  const test::CommandResult same = test::runCommand(simulate + " --replay " + bag);
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  EXPECT_NE(same.out.find("largest difference 0\n"), std::string::npos) << same.out;
  EXPECT_NE(same.out.find("replayed " + std::to_string(logged.size()) + " inputs"),
            std::string::npos)
      << same.out;
  // The bag holds the node's checkpoints (start, set_state, reconfigure, reset): the replay
  // started at tick 0 and re-synchronised at each (the reconfiguration included).
  ASSERT_GE(recorded.size(), 4u);
  EXPECT_EQ(recorded[0].cause, "start");
  EXPECT_NE(same.out.find("started at the checkpoint of tick 0"), std::string::npos) << same.out;
  const std::string with_checkpoints = dir + "/replay_checkpoints.bag";
  // Recorded mid-run: the recorder got the latched checkpoint of set_state, but the inputs before
  // it, and between an older checkpoint and it, are not in the bag. It replays from the first
  // checkpoint after which every input is there, bit for bit.
  std::size_t at_set_state = 0;
  while (at_set_state < recorded.size() && recorded[at_set_state].cause != "set_state")
    ++at_set_state;
  ASSERT_LT(at_set_state, recorded.size());
  std::vector<InputLog> later;
  for (const InputLog& log : logged)
    if (log.seq >= recorded[at_set_state].next_input) later.push_back(log);
  ASSERT_FALSE(later.empty());
  const std::string mid_run = dir + "/replay_mid_run.bag";
  writeBag(mid_run, state_.messages(), later, SIZE_MAX, recorded);
  const test::CommandResult from_mid = test::runCommand(simulate + " --replay " + mid_run);
  EXPECT_EQ(from_mid.exit_code, 0) << from_mid.out << from_mid.err;
  EXPECT_NE(from_mid.out.find("started at the checkpoint of tick " +
                              std::to_string(recorded[at_set_state].tick)),
            std::string::npos)
      << from_mid.out;
  EXPECT_NE(from_mid.out.find("passed over " + std::to_string(at_set_state) + " earlier"),
            std::string::npos)
      << from_mid.out;
  EXPECT_NE(from_mid.out.find("largest difference 0\n"), std::string::npos) << from_mid.out;
  // Damaged checkpoints are named, not reported as a difference or blamed on --config.
  const auto damaged = [&](const std::function<void(Checkpoint*)>& damage,
                           const std::string& message) {
    std::vector<Checkpoint> tampered = recorded;
    damage(&tampered[at_set_state]);
    writeBag(mid_run, state_.messages(), later, SIZE_MAX, tampered);
    const test::CommandResult r = test::runCommand(simulate + " --replay " + mid_run);
    EXPECT_EQ(r.exit_code, 6) << message << "\n" << r.out << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.out << r.err;
  };
  damaged(
      [](Checkpoint* c) {
        const size_t q1 = c->state.find("\nstate ") + 7;
        c->state.replace(q1, c->state.find(' ', q1) - q1, "0x1.8p+0");  // q1 = 1.5
      },
      "holds q1 = 1.5 where the bag's state there has");
  damaged([](Checkpoint* c) { c->next_input = 1000000; }, "the checkpoint is damaged");
  damaged([](Checkpoint* c) { c->state += "junk 1 2\n"; }, "checkpoint field 'junk' is not one");
  // The same bag without its checkpoints is refused by name (it once reported 74.28).
  writeBag(mid_run, state_.messages(), later);
  const test::CommandResult no_start = test::runCommand(simulate + " --replay " + mid_run);
  EXPECT_EQ(no_start.exit_code, 6);
  EXPECT_NE(no_start.err.find("has no ~checkpoint to start from"), std::string::npos)
      << no_start.err;
  // Without the reconfiguration's checkpoint the run after it cannot match.
  std::vector<Checkpoint> without_reconfigure;
  for (const Checkpoint& c : recorded)
    if (c.cause != "reconfigure") without_reconfigure.push_back(c);
  writeBag(with_checkpoints, state_.messages(), logged, SIZE_MAX, without_reconfigure);
  const test::CommandResult unsynced = test::runCommand(simulate + " --replay " + with_checkpoints);
  EXPECT_EQ(unsynced.exit_code, 6) << unsynced.out;

  // Without the first input: named as not recorded, not reported as a difference far from it.
  const test::CommandResult differs = test::runCommand(simulate + " --replay " + cut);
  EXPECT_EQ(differs.exit_code, 6) << differs.out << differs.err;
  EXPECT_NE(differs.err.find("input 0 of /kane_sim/input_log were not recorded: the recording "
                             "began after the node had received them"),
            std::string::npos)
      << differs.err;
  writeBag(cut, state_.messages(), logged, 3);  // a gap in the middle
  const test::CommandResult gap = test::runCommand(simulate + " --replay " + cut);
  EXPECT_EQ(gap.exit_code, 6) << gap.out << gap.err;
  EXPECT_NE(gap.err.find("input 3 of /kane_sim/input_log were not recorded (a gap in the bag)"),
            std::string::npos)
      << gap.err;
  // A gap with checkpoints around it: compared up to the gap, named with the states it left
  // uncompared, re-synchronised at the next checkpoint that holds the missing inputs; exit 6
  // unless --accept-gaps (it once started after the gap and said "largest difference 0").
  const auto without = [&](std::uint64_t first, std::uint64_t last) {
    std::vector<InputLog> kept;
    for (const InputLog& log : logged)
      if (log.seq < first || log.seq > last) kept.push_back(log);
    return kept;
  };
  const Checkpoint& reconfigured =
      *std::find_if(recorded.begin(), recorded.end(),
                    [](const Checkpoint& c) { return c.cause == "reconfigure"; });
  ASSERT_GE(reconfigured.next_input, 3u);
  const std::uint64_t lost = reconfigured.next_input - 2;  // two inputs before that checkpoint
  writeBag(cut, state_.messages(), without(lost, lost + 1), SIZE_MAX, recorded);
  const std::string lost_text = "inputs " + std::to_string(lost) + "-" + std::to_string(lost + 1) +
                                " of /kane_sim/input_log were not recorded (a gap in the bag)";
  const test::CommandResult middle = test::runCommand(simulate + " --replay " + cut);
  EXPECT_EQ(middle.exit_code, 6) << middle.out << middle.err;
  EXPECT_NE(middle.err.find(lost_text), std::string::npos) << middle.err;
  EXPECT_NE(middle.err.find("states from t = "), std::string::npos) << middle.err;
  EXPECT_NE(middle.err.find("re-synchronised at the checkpoint of tick " +
                            std::to_string(reconfigured.tick)),
            std::string::npos)
      << middle.err;
  EXPECT_NE(middle.out.find("started at the checkpoint of tick 0"), std::string::npos)
      << middle.out;
  const test::CommandResult accepted =
      test::runCommand(simulate + " --replay " + cut + " --accept-gaps");
  EXPECT_EQ(accepted.exit_code, 0) << accepted.out << accepted.err;
  EXPECT_NE(accepted.out.find("largest difference 0\n"), std::string::npos) << accepted.out;
  EXPECT_NE(accepted.out.find(" not compared: gaps"), std::string::npos) << accepted.out;
  // Recorded mid-run, with inputs lost after the last checkpoint: the gap is named, not the
  // inputs from before the recording (every mid-run bag lacks those).
  const Checkpoint& last_checkpoint = recorded.back();
  std::vector<InputLog> tail;
  for (const InputLog& log : later)
    if (log.seq <= last_checkpoint.next_input || log.seq > last_checkpoint.next_input + 1)
      tail.push_back(log);
  ASSERT_GT(tail.back().seq, last_checkpoint.next_input + 1) << "no input after the gap";
  writeBag(mid_run, state_.messages(), tail, SIZE_MAX, recorded);
  const test::CommandResult late_gap = test::runCommand(simulate + " --replay " + mid_run);
  EXPECT_EQ(late_gap.exit_code, 6) << late_gap.out << late_gap.err;
  EXPECT_NE(late_gap.err.find("input " + std::to_string(last_checkpoint.next_input + 1) +
                              " of /kane_sim/input_log were not recorded (a gap in the bag)"),
            std::string::npos)
      << late_gap.err;
  EXPECT_NE(late_gap.err.find("no later ~checkpoint holds the missing inputs"), std::string::npos)
      << late_gap.err;
  EXPECT_EQ(late_gap.err.find("after the bag's first ~checkpoint"), std::string::npos)
      << late_gap.err;
  EXPECT_NE(late_gap.out.find("largest difference 0\n"), std::string::npos) << late_gap.out;
  // The inputs after the gap were lost to it, not "after the bag's last state".
  EXPECT_EQ(late_gap.err.find("after the bag's last state"), std::string::npos) << late_gap.err;
  // States no run can have: named, never compared (t = inf once passed as tick 0).
  for (const auto& [time, q1, message] : std::vector<std::tuple<double, double, std::string>>{
           {INFINITY, 0.5, "has sim_time inf s, not in [0, 1e+07] s"},
           {1e300, 0.5, "has sim_time 1e+300 s"},
           {-1.0, 0.5, "has sim_time -1 s"},
           {0.0105, 0.5, "is not on the physics grid"},
           {0.01, std::nan(""), "holds nan: the node never publishes one"}}) {
    std::vector<MechanismState> states = state_.messages();
    states.back().sim_time = time;
    states.back().q[0] = q1;
    writeBag(cut, states, logged);
    const test::CommandResult bad = test::runCommand(simulate + " --replay " + cut);
    EXPECT_EQ(bad.exit_code, 6) << message;
    EXPECT_NE(bad.err.find(message), std::string::npos) << bad.err;
  }
  // A bag whose last state is 10^6 s of sim time away (10^9 steps): Ctrl-C ends the replay
  // with 128 + SIGINT, saying how far it compared.
  {
    std::vector<MechanismState> states = state_.messages();
    states.back().sim_time = 1e6;
    writeBag(cut, states, logged);
    const test::CommandResult stopped =
        test::runCommand("timeout --preserve-status -s INT 1 " + simulate + " --replay " + cut);
    EXPECT_EQ(stopped.exit_code, 130) << stopped.out << stopped.err;
    EXPECT_NE(stopped.err.find("interrupted at t = "), std::string::npos) << stopped.err;
  }
  // Hostile: not a bag, a bag without inputs, a negative tolerance.
  const test::CommandResult not_bag = test::runCommand(simulate + " --replay " + config);
  EXPECT_EQ(not_bag.exit_code, 6);
  EXPECT_NE(not_bag.err.find("cannot read --replay"), std::string::npos) << not_bag.err;
  writeBag(cut, state_.messages(), {});
  const test::CommandResult no_inputs = test::runCommand(simulate + " --replay " + cut);
  EXPECT_EQ(no_inputs.exit_code, 6);
  EXPECT_NE(no_inputs.err.find("input_log"), std::string::npos) << no_inputs.err;
  const test::CommandResult tolerance =
      test::runCommand(simulate + " --replay " + bag + " --tolerance -1");
  EXPECT_EQ(tolerance.exit_code, 2);
}

}  // namespace
}  // namespace kane_sim
