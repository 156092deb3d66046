// Two sims side by side in namespaces robot_a and robot_b with frame prefixes
// (test/node/namespaces.test): no mixing of topics or frames.
#include <gtest/gtest.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "kane_sim/MechanismState.h"
#include "node_test_utils.h"

namespace kane_sim {
namespace {

using test::Recorder;

TEST(Namespaces, TwoInstancesKeepTheirTopicsAndFramesApart) {
  ros::NodeHandle nh;
  Recorder<MechanismState> a(nh, "/robot_a/mechanism_state");
  Recorder<MechanismState> b(nh, "/robot_b/mechanism_state");
  Recorder<sensor_msgs::JointState> root(nh, "/joint_states");
  ros::Publisher torque_a =
      test::connectedPublisher<std_msgs::Float64>(nh, "/robot_a/torque_command");
  ASSERT_TRUE(a.waitForCount(1, 15.0));
  ASSERT_TRUE(b.waitForCount(1, 15.0));
  test::send(torque_a, 6.0);
  ASSERT_TRUE(test::waitFor([&] { return a.last().applied_torque == 6.0; }, 3.0));
  test::sleepWall(0.2);
  EXPECT_EQ(b.last().applied_torque, 0.0);
  EXPECT_NE(a.last().q[0], b.last().q[0]);
  EXPECT_EQ(a.last().header.frame_id, "robot_a/mechanism");
  EXPECT_EQ(b.last().header.frame_id, "robot_b/mechanism");
  EXPECT_EQ(root.count(), 0u) << "nothing is published outside the namespaces";

  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  for (const char* frame : {"robot_a/rod1", "robot_a/slider4", "robot_b/rod1", "robot_b/slider4"}) {
    std::string error;
    EXPECT_TRUE(buffer.canTransform("world", frame, ros::Time(0), ros::Duration(3.0), &error))
        << frame << ": " << error;
  }
  EXPECT_FALSE(buffer._frameExists("rod1"));
}

}  // namespace
}  // namespace kane_sim
