// joint_states and tf of a running sim (test/node/topics.test).
#include <cmath>

#include <gtest/gtest.h>
#include <sensor_msgs/JointState.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <visualization_msgs/MarkerArray.h>

#include "kane_sim/MechanismState.h"
#include "node_test_utils.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

using test::Recorder;

TEST(Topics, JointStatesArriveAtPublishRateWithFourFiniteJoints) {
  ros::NodeHandle nh;
  Recorder<sensor_msgs::JointState> js(nh, "joint_states");
  ASSERT_TRUE(js.waitForCount(1, 15.0)) << "no joint_states";
  js.clear();
  const auto start = ros::WallTime::now();
  test::sleepWall(3.0);
  const auto msgs = js.messages();
  const double wall = (ros::WallTime::now() - start).toSec();
  const double rate = msgs.size() / wall;
  EXPECT_NEAR(rate, 100.0, 10.0) << msgs.size() << " messages in " << wall << " s";
  for (size_t i = 0; i < msgs.size(); ++i) {
    const auto& m = msgs[i];
    ASSERT_EQ(m.name.size(), 4u);
    EXPECT_EQ(m.name[0], "crank_joint");
    EXPECT_EQ(m.name[3], "slider4_joint");
    ASSERT_EQ(m.position.size(), 4u);
    ASSERT_EQ(m.velocity.size(), 4u);
    ASSERT_EQ(m.effort.size(), 4u);
    for (int j = 0; j < 4; ++j) {
      EXPECT_TRUE(std::isfinite(m.position[j]) && std::isfinite(m.velocity[j]) &&
                  std::isfinite(m.effort[j]));
    }
    if (i > 0) {
      EXPECT_GT(m.header.stamp, msgs[i - 1].header.stamp);
    }
  }
}

TEST(Topics, TfFramesAgreeWithJointStates) {
  ros::NodeHandle nh;
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  Recorder<sensor_msgs::JointState> js(nh, "joint_states");
  const double L = 0.25;
  ASSERT_TRUE(js.waitForCount(50, 15.0));
  test::sleepWall(0.3);  // let tf catch up with the joint_states we compare against
  const auto msgs = js.messages();
  int checked = 0;
  for (size_t i = msgs.size() - 30; i < msgs.size() - 5; ++i) {
    const auto& m = msgs[i];
    const double q1 = m.position[0], q2 = m.position[3];
    std::string error;
    for (const char* frame : {"rod1", "rod2", "slider3", "slider4"})
      ASSERT_TRUE(buffer.canTransform("world", frame, m.header.stamp, ros::Duration(1.0), &error))
          << frame << ": " << error;
    // The kinematic chain: rod 1's frame at O, rod 2's at A = 2L (cos q1, sin q1), each with
    // x along its rod; the sliders at B and C on the rail.
    const auto rod1 = buffer.lookupTransform("mechanism", "rod1", m.header.stamp);
    const auto rod2 = buffer.lookupTransform("mechanism", "rod2", m.header.stamp);
    const auto s3 = buffer.lookupTransform("mechanism", "slider3", m.header.stamp);
    const auto s4 = buffer.lookupTransform("mechanism", "slider4", m.header.stamp);
    EXPECT_NEAR(rod1.transform.translation.x, 0.0, 1e-9);
    EXPECT_NEAR(rod1.transform.translation.y, 0.0, 1e-9);
    EXPECT_NEAR(rod2.transform.translation.x, 2 * L * std::cos(q1), 1e-9);
    EXPECT_NEAR(rod2.transform.translation.y, 2 * L * std::sin(q1), 1e-9);
    EXPECT_NEAR(s3.transform.translation.x, m.position[2], 1e-9);
    EXPECT_NEAR(s4.transform.translation.x, q2, 1e-9);
    // Rod 1 turns by q1 about the plane normal, rod 2 by -q1.
    EXPECT_NEAR(2 * std::atan2(rod1.transform.rotation.z, rod1.transform.rotation.w),
                std::remainder(q1, 2 * M_PI), 1e-9);
    EXPECT_NEAR(
        std::remainder(2 * std::atan2(rod2.transform.rotation.z, rod2.transform.rotation.w) + q1,
                       2 * M_PI),
        0.0, 1e-9);
    ++checked;
  }
  EXPECT_EQ(checked, 25);
  // The textbook's frame hangs from the pivot with x down: O is 2 m up, slider 3 below it.
  const auto world_s3 = buffer.lookupTransform("world", "slider3", ros::Time(0));
  EXPECT_NEAR(world_s3.transform.translation.x, 0.0, 1e-9);
  EXPECT_LT(world_s3.transform.translation.z, 2.0);
  EXPECT_GT(world_s3.transform.translation.z, 2.0 - 4 * L - 1e-9);
}

TEST(Topics, MarkersArriveInTheirLinksFramesWithStableIds) {
  ros::NodeHandle nh;
  Recorder<visualization_msgs::MarkerArray> markers(nh, "visualization_markers");
  ASSERT_TRUE(markers.waitForCount(20, 15.0));
  const auto msgs = markers.messages();
  for (const auto& array : msgs) {
    ASSERT_EQ(array.markers.size(), msgs.front().markers.size());
    for (size_t i = 0; i < array.markers.size(); ++i) {
      EXPECT_EQ(array.markers[i].header.frame_id,
                test::markerFrame(array.markers[i].ns, array.markers[i].id));
      EXPECT_EQ(array.markers[i].ns, msgs.front().markers[i].ns);
      EXPECT_EQ(array.markers[i].id, msgs.front().markers[i].id);
    }
  }
}

}  // namespace
}  // namespace kane_sim
