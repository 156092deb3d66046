// `simulate --bag`: the bag reads back with every topic, the right counts, increasing stamps,
// a latched /tf_static holding world -> mechanism, and the same numbers as the CSV of the run.
#include <sys/wait.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/JointState.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <yaml-cpp/yaml.h>

#include "kane_sim/InputLog.h"
#include "kane_sim/MechanismState.h"
#include "kane_sim/ServoState.h"
#include "kane_sim/ros/messages.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

std::vector<std::vector<double>> readCsv(const std::string& path) {
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  std::string header;
  return test::parseCsv(text, &header);
}

class SimulateBag : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ros::Time::init();
    const std::string cmd = std::string(KANE_SIM_SIMULATE_EXE) + " --config " +
                            test::configPath("mechanism.yaml") +
                            " --duration 3 --output-rate 50 --torque-step 1,0,6 --bag " +
                            bag_path() + " --csv " + csv_path() + " 2>/dev/null";
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << cmd;
  }
  static std::string bag_path() { return ::testing::TempDir() + "/simulate_test.bag"; }
  static std::string csv_path() { return ::testing::TempDir() + "/simulate_test.csv"; }
};

TEST_F(SimulateBag, EveryTopicWithExpectedCountsAndIncreasingStamps) {
  rosbag::Bag bag(bag_path());
  std::map<std::string, int> counts;
  std::map<std::string, ros::Time> last;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    const std::string& topic = m.getTopic();
    if (counts[topic]++ > 0) {
      EXPECT_GT(m.getTime(), last[topic]) << topic;
    }
    last[topic] = m.getTime();
  }
  EXPECT_EQ(counts["/joint_states"], 151);  // t = 0, 0.02, ..., 3.0
  EXPECT_EQ(counts["/tf"], 151);
  EXPECT_EQ(counts["/mechanism_state"], 151);
  EXPECT_EQ(counts["/visualization_markers"], 151);
  EXPECT_EQ(counts["/clock"], 151);
  EXPECT_EQ(counts["/tf_static"], 1);
  // The profile's commands as the node logs them on ~input_log: the held value is sent again
  // every half command.timeout (0.5 s), so ticks 0, 250, ..., 3000.
  EXPECT_EQ(counts["/kane_sim/input_log"], 13);
  EXPECT_EQ(counts.size(), 7u);
}

TEST_F(SimulateBag, TheInputLogHoldsTheProfilesCommandsAtTheirTicks) {
  rosbag::Bag bag(bag_path());
  std::uint64_t seq = 0;
  for (const rosbag::MessageInstance& m :
       rosbag::View(bag, rosbag::TopicQuery("/kane_sim/input_log"))) {
    const auto input = m.instantiate<kane_sim::InputLog>();
    ASSERT_TRUE(input);
    EXPECT_EQ(input->seq, seq++);
    EXPECT_EQ(input->kind, kane_sim::InputLog::TORQUE);
    EXPECT_EQ(input->tick, 250 * input->seq);
    // The step: 0 N m before t = 1 s, 6 N m from it (tick 1000 at 1 kHz).
    EXPECT_EQ(input->value, input->tick < 1000 ? 0.0 : 6.0) << input->tick;
    // Stamped like the state at that tick (simulate's clock: 1e9 s + sim time).
    EXPECT_NEAR(input->header.stamp.toSec() - 1e9, 1e-3 * input->tick, 1e-6);
  }
  EXPECT_EQ(seq, 13u);
}

TEST_F(SimulateBag, TfStaticIsLatchedAndHoldsWorldToMechanism) {
  rosbag::Bag bag(bag_path());
  rosbag::View view(bag, rosbag::TopicQuery("/tf_static"));
  ASSERT_EQ(view.size(), 1u);
  const rosbag::View::iterator it = view.begin();  // owns the MessageInstance below
  const rosbag::MessageInstance& m = *it;
  EXPECT_EQ(m.getConnectionHeader()->at("latching"), "1");
  const auto tf = m.instantiate<tf2_msgs::TFMessage>();
  ASSERT_TRUE(tf);
  ASSERT_EQ(tf->transforms.size(), 1u);
  EXPECT_EQ(tf->transforms[0].header.frame_id, "world");
  EXPECT_EQ(tf->transforms[0].child_frame_id, "mechanism");
  EXPECT_EQ(tf->transforms[0].transform.translation.z, 2.0);
}

TEST_F(SimulateBag, ValuesEqualTheCsvOfTheSameRun) {
  const auto rows = readCsv(csv_path());
  ASSERT_EQ(rows.size(), 151u);
  rosbag::Bag bag(bag_path());
  size_t i = 0;
  for (const rosbag::MessageInstance& m :
       rosbag::View(bag, rosbag::TopicQuery("/mechanism_state"))) {
    const auto s = m.instantiate<MechanismState>();
    ASSERT_TRUE(s);
    ASSERT_LT(i, rows.size());
    const auto& r = rows[i++];
    // The CSV prints each double's shortest exact form: the values round-trip exactly.
    EXPECT_EQ(s->sim_time, r[0]);
    EXPECT_EQ(s->q[0], r[1]);
    EXPECT_EQ(s->q[1], r[2]);
    EXPECT_EQ(s->u[0], r[3]);
    EXPECT_EQ(s->u[1], r[4]);
    EXPECT_EQ(s->total_energy, r[5]);
    EXPECT_EQ(s->applied_torque, r[8]);
    EXPECT_EQ(s->motor_work, r[9]);
    EXPECT_EQ(m.getTime(), simStamp(r[0]));
    EXPECT_EQ(s->header.stamp, simStamp(r[0]));
  }
  EXPECT_EQ(i, rows.size());
  // The torque step at t = 1 s shows in the applied torque.
  EXPECT_EQ(rows[49][8], 0.0);
  EXPECT_EQ(rows[50][8], 6.0);
}

TEST_F(SimulateBag, MarkersHaveStableIdsAndTheirLinksFrames) {
  rosbag::Bag bag(bag_path());
  rosbag::View view(bag, rosbag::TopicQuery("/visualization_markers"));
  std::vector<std::pair<std::string, int>> first_ids;
  for (const rosbag::MessageInstance& m : view) {
    const auto array = m.instantiate<visualization_msgs::MarkerArray>();
    ASSERT_TRUE(array);
    std::vector<std::pair<std::string, int>> ids;
    for (const auto& marker : array->markers) {
      EXPECT_EQ(marker.header.frame_id, test::markerFrame(marker.ns, marker.id));
      EXPECT_TRUE(marker.frame_locked);
      ids.emplace_back(marker.ns, marker.id);
    }
    if (first_ids.empty()) first_ids = ids;
    EXPECT_EQ(ids, first_ids);
  }
  // pins x3, rail, spring, torque arrow (the rods and sliders are the URDF's, drawn by RobotModel)
  EXPECT_EQ(first_ids.size(), 6u);
}

// SIGINT during a long --bag run: the bag is closed properly (index written) and renamed into
// place, so what was simulated reads back, every message in order; exit 130.
// `simulate --bag` of the config `root` (written to a scratch file) with `args`; the bag's path.
std::string writeBagOf(const YAML::Node& root, const std::string& name, const std::string& args) {
  ros::Time::init();
  const std::string config = ::testing::TempDir() + "/simulate_" + name + ".yaml";
  std::ofstream(config) << root;
  const std::string bag_file = ::testing::TempDir() + "/simulate_" + name + ".bag";
  const std::string cmd = std::string(KANE_SIM_SIMULATE_EXE) + " --config " + config + " " + args +
                          " --bag " + bag_file + " 2>/dev/null";
  const int status = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << cmd;
  return bag_file;
}

// Sensors on (config/sensors.yaml over the default): /joint_states holds the readings, 100 Hz,
// each stamped when it arrives (5..7 ms after its sample, so off the 10 ms output grid), within
// noise, bias and half a count of the truth on /joint_states_true at the sample's instant.
TEST(SimulateBagSensors, ReadingsOnJointStatesTruthOnJointStatesTrue) {
  YAML::Node root = YAML::LoadFile(test::configPath("mechanism.yaml"));
  for (const auto& e : YAML::LoadFile(test::configPath("sensors.yaml"))["sensors"])
    root["sensors"][e.first.Scalar()] = e.second;
  std::string bag_file;
  ASSERT_NO_FATAL_FAILURE(bag_file = writeBagOf(root, "sensors", "--duration 2 --torque 3"));
  rosbag::Bag bag(bag_file);
  std::map<ros::Time, sensor_msgs::JointState> truth;
  std::vector<sensor_msgs::JointState> readings;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (m.getTopic() == "/joint_states_true")
      truth[m.getTime()] = *m.instantiate<sensor_msgs::JointState>();
    if (m.getTopic() == "/joint_states")
      readings.push_back(*m.instantiate<sensor_msgs::JointState>());
  }
  EXPECT_EQ(truth.size(), 201u);
  ASSERT_EQ(readings.size(), 200u);  // sampled at 0 .. 1.99 s; the one sampled at 2 s is in flight
  const double count = 2 * M_PI / 4096;
  for (const sensor_msgs::JointState& r : readings) {
    // The sample instant is the 10 ms grid point 5..7 ms before the stamp.
    const double arrival = (r.header.stamp - simStamp(0)).toSec();
    const double sampled = 0.01 * std::floor(arrival / 0.01 + 1e-6);
    const double delay = arrival - sampled;
    EXPECT_GE(delay, 0.005 - 1e-6);
    EXPECT_LE(delay, 0.007 + 1e-6);
    const auto at = truth.find(simStamp(sampled));
    ASSERT_NE(at, truth.end()) << sampled;
    // σ 0.002 rad, bias walk 0.0005 √2 rad, half a count: six σ of each at most.
    EXPECT_NEAR(r.position[0], at->second.position[0],
                6 * 0.002 + 6 * 0.0005 * std::sqrt(2.0) + count);
    EXPECT_NEAR(std::remainder(r.position[0], count), 0.0, 1e-9);
    EXPECT_EQ(r.effort[0], at->second.effort[0]);
  }
}

// In a servo mode the bag holds /servo_state as the node publishes it, one per state, with
// the setpoint of the profile (it once lacked the topic).
TEST(SimulateBagServo, AServoRunsBagHoldsServoState) {
  YAML::Node root = YAML::LoadFile(test::configPath("mechanism.yaml"));
  root["command"]["mode"] = "position";
  std::string bag_file;
  ASSERT_NO_FATAL_FAILURE(bag_file = writeBagOf(root, "servo", "--duration 1 --torque 0.8"));
  rosbag::Bag bag(bag_file);
  std::vector<ServoState> servo;
  size_t states = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (m.getTopic() == "/servo_state") servo.push_back(*m.instantiate<ServoState>());
    states += m.getTopic() == "/mechanism_state";
  }
  ASSERT_EQ(servo.size(), states);
  EXPECT_EQ(servo.size(), 101u);
  EXPECT_EQ(servo.back().setpoint, 0.8);
  EXPECT_NEAR(servo.back().measured, 0.8, 0.05);  // held near the setpoint after 1 s
}

TEST(SimulateBagInterrupted, TheBagOfAnInterruptedRunReadsBack) {
  ros::Time::init();
  const std::string path = ::testing::TempDir() + "/interrupted.bag";
  const std::string cmd = "( " + std::string(KANE_SIM_SIMULATE_EXE) + " --config " +
                          test::configPath("mechanism.yaml") +
                          " --duration 100000 --output-rate 10 --bag " + path +
                          " & pid=$!; sleep 1; kill -INT $pid; wait $pid )";
  const test::CommandResult r = test::runCommand(cmd);
  ASSERT_EQ(r.exit_code, 130) << r.err;
  rosbag::Bag bag(path);
  size_t states = 0;
  ros::Time last;
  for (const rosbag::MessageInstance& m :
       rosbag::View(bag, rosbag::TopicQuery("/mechanism_state"))) {
    EXPECT_GT(m.getTime(), last);
    last = m.getTime();
    ++states;
  }
  EXPECT_GT(states, 100u);
}

}  // namespace
}  // namespace kane_sim
