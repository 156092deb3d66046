// The robot ROS knows (test/node/robot_description*.test, rsp_tf.test): robot_description
// parses with check_urdf and holds the config; robot_state_publisher, fed the node's
// joint_states, reproduces every frame the node publishes; with publish_tf false the node
// leaves tf to robot_state_publisher.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <ros/master.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <tf2_msgs/TFMessage.h>
#include <urdf_parser/urdf_parser.h>
#include <Eigen/Geometry>

#include "kane_sim/config/load_config.h"
#include "node_test_utils.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

using test::Recorder;

std::string robotDescription() {
  std::string urdf;
  const bool found =
      test::waitFor([&] { return ros::param::get("robot_description", urdf); }, 10.0);
  return found ? urdf : "";
}

// The config file the node under test was launched with (the .test's ~expected_config).
Config expectedConfig() {
  std::string path;
  ros::param::get("~expected_config", path);
  return loadConfigFile(path).config;
}

TEST(RobotDescription, ParsesWithCheckUrdfAndHoldsTheConfig) {
  const std::string urdf = robotDescription();
  ASSERT_FALSE(urdf.empty()) << "robot_description is not set";
  const std::string file = "/tmp/kane_sim_robot_description_" + std::to_string(getpid()) + ".urdf";
  std::ofstream(file) << urdf;
  const test::CommandResult check = test::runCommand("check_urdf " + file);
  std::remove(file.c_str());
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  EXPECT_NE(check.out.find("Successfully Parsed XML"), std::string::npos) << check.out;
  EXPECT_NE(check.out.find("root Link: world"), std::string::npos) << check.out;

  const Config c = expectedConfig();
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf);
  ASSERT_TRUE(model);
  for (const char* rod : {"rod1", "rod2"}) {
    EXPECT_EQ(model->getLink(rod)->inertial->mass, c.mechanism.rod_mass) << rod;
    EXPECT_EQ(model->getLink(rod)->inertial->izz, c.mechanism.rod_inertia) << rod;
    const auto* cylinder =
        dynamic_cast<const urdf::Cylinder*>(model->getLink(rod)->visual->geometry.get());
    ASSERT_NE(cylinder, nullptr);
    EXPECT_DOUBLE_EQ(cylinder->length, 2 * c.mechanism.rod_half_length);
  }
  EXPECT_EQ(model->getLink("slider3")->inertial->mass, c.mechanism.slider3_mass);
  EXPECT_EQ(model->getLink("slider4")->inertial->mass, c.mechanism.slider4_mass);
  EXPECT_DOUBLE_EQ(model->getJoint("coupler_joint")->parent_to_joint_origin_transform.position.x,
                   2 * c.mechanism.rod_half_length);
}

Eigen::Isometry3d toEigen(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.translate(Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z));
  iso.rotate(Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z));
  return iso;
}

using Keyed = std::map<std::pair<std::string, ros::Time>, geometry_msgs::TransformStamped>;
Keyed byChildAndStamp(const std::vector<tf2_msgs::TFMessage>& messages) {
  Keyed out;
  for (const auto& m : messages)
    for (const auto& t : m.transforms) out[{t.child_frame_id, t.header.stamp}] = t;
  return out;
}

// robot_state_publisher (its /tf remapped to /rsp/tf) computes from robot_description and the
// node's joint_states the same frames the node publishes: same parents, same poses.
TEST(RobotDescription, RobotStatePublisherReproducesEveryFrame) {
  ros::NodeHandle nh;
  Recorder<tf2_msgs::TFMessage> node_tf(nh, "/tf"), rsp_tf(nh, "/rsp/tf");
  Recorder<tf2_msgs::TFMessage> node_static(nh, "/tf_static"), rsp_static(nh, "/rsp/tf_static");
  ASSERT_TRUE(rsp_tf.waitForCount(40, 20.0)) << "robot_state_publisher publishes nothing";
  ASSERT_TRUE(node_static.waitForCount(1, 5.0) && rsp_static.waitForCount(1, 5.0));
  test::sleepWall(0.2);
  const Keyed mine = byChildAndStamp(node_tf.messages());
  const Keyed theirs = byChildAndStamp(rsp_tf.messages());
  int compared = 0;
  std::set<std::string> frames;
  for (const auto& [key, rsp] : theirs) {
    const auto it = mine.find(key);
    if (it == mine.end()) continue;  // rsp publishes at its own rate: compare common stamps
    const auto& node = it->second;
    EXPECT_EQ(node.header.frame_id, rsp.header.frame_id) << key.first;
    const Eigen::Isometry3d a = toEigen(node.transform), b = toEigen(rsp.transform);
    EXPECT_LT((a.translation() - b.translation()).norm(), 1e-9) << key.first;
    EXPECT_LT(Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle(), 1e-9) << key.first;
    frames.insert(key.first);
    ++compared;
  }
  EXPECT_GE(compared, 80) << "too few common stamps to compare";
  EXPECT_EQ(frames, (std::set<std::string>{"rod1", "rod2", "slider3", "slider4"}));
  const auto a = node_static.last().transforms.at(0), b = rsp_static.last().transforms.at(0);
  EXPECT_EQ(a.header.frame_id, b.header.frame_id);
  EXPECT_EQ(a.child_frame_id, b.child_frame_id);
  EXPECT_LT((toEigen(a.transform).matrix() - toEigen(b.transform).matrix()).norm(), 1e-9);
}

// Who publishes a topic, from the master.
std::set<std::string> publishersOf(const std::string& topic) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  std::set<std::string> out;
  if (!ros::master::execute("getSystemState", args, result, payload, true)) return out;
  XmlRpc::XmlRpcValue& publishers = payload[0];
  for (int i = 0; i < publishers.size(); ++i)
    if (static_cast<std::string>(publishers[i][0]) == topic)
      for (int j = 0; j < publishers[i][1].size(); ++j)
        out.insert(static_cast<std::string>(publishers[i][1][j]));
  return out;
}

// sim.launch robot_state_publisher:=true: the node publishes no tf, robot_state_publisher
// publishes the whole tree, and it agrees with the node's joint_states.
TEST(RspTf, RobotStatePublisherOwnsTheTreeAndItMatchesJointStates) {
  ros::NodeHandle nh;
  Recorder<sensor_msgs::JointState> js(nh, "joint_states");
  Recorder<tf2_msgs::TFMessage> tf(nh, "/tf");
  ASSERT_TRUE(js.waitForCount(50, 20.0));
  test::sleepWall(0.3);
  EXPECT_EQ(publishersOf("/tf"), std::set<std::string>{"/robot_state_publisher"});
  EXPECT_EQ(publishersOf("/tf_static"), std::set<std::string>{"/robot_state_publisher"});
  const Keyed frames = byChildAndStamp(tf.messages());
  const double L = 0.25;
  int checked = 0;
  for (const auto& m : js.messages()) {
    const auto rod1 = frames.find({"rod1", m.header.stamp});
    const auto rod2 = frames.find({"rod2", m.header.stamp});
    const auto s4 = frames.find({"slider4", m.header.stamp});
    if (rod1 == frames.end() || rod2 == frames.end() || s4 == frames.end()) continue;
    // B is rod 2's far end (x_B = slider3_joint); C is q2 along the rail.
    const Eigen::Isometry3d b_pose =
        toEigen(rod1->second.transform) * toEigen(rod2->second.transform);
    EXPECT_NEAR((b_pose * Eigen::Vector3d(2 * L, 0, 0)).x(), m.position[2], 1e-9);
    EXPECT_NEAR(s4->second.transform.translation.x, m.position[3], 1e-12);
    ++checked;
  }
  EXPECT_GE(checked, 40) << "robot_state_publisher's tf did not cover the joint_states";
}

}  // namespace
}  // namespace kane_sim
