// Stamps: one per physics tick for everything published at it (stamps.test: wall clock, sensor
// readings without latency beside the truth), and a moved state stamped after every earlier
// one with its pose on /tf at that stamp (resets_paused_clock.test: /clock mode, paused, where
// sim time stands still).
#include <cmath>
#include <map>

#include <gtest/gtest.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Empty.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "kane_sim/MechanismState.h"
#include "kane_sim/ResetEvent.h"
#include "kane_sim/SetState.h"
#include "node_test_utils.h"

namespace kane_sim {
namespace {

using test::Recorder;

// With latency 0 every reading is sampled and delivered at a publish tick, where the truth goes
// out too: each truth message has a reading with its very stamp (they were ~65 µs apart).
TEST(Stamps, AReadingAndTheTruthOfOneTickCarryOneStamp) {
  ros::NodeHandle nh;
  Recorder<sensor_msgs::JointState> readings(nh, "joint_states");
  Recorder<sensor_msgs::JointState> truth(nh, "joint_states_true");
  ASSERT_TRUE(truth.waitForCount(100, 20.0));
  ASSERT_TRUE(readings.waitForCount(100, 5.0));
  std::map<ros::Time, sensor_msgs::JointState> by_stamp;
  for (const auto& r : readings.messages()) by_stamp[r.header.stamp] = r;
  size_t paired = 0;
  for (const auto& t : truth.messages()) {
    const auto it = by_stamp.find(t.header.stamp);
    if (it == by_stamp.end()) continue;  // before the readings' subscription connected
    // No noise configured: the reading is the truth of its tick.
    EXPECT_EQ(it->second.position, t.position);
    ++paired;
  }
  EXPECT_GE(paired, 90u) << "of " << truth.count() << " truth messages";
}

// q1 from rod 1's rotation about z (the mechanism frame's k).
double rod1Angle(const geometry_msgs::TransformStamped& t) {
  const auto& q = t.transform.rotation;
  return 2.0 * std::atan2(q.z, q.w);
}

// Paused in /clock mode: set_state and reset do not advance sim time, yet the moved state gets a
// later stamp, and /tf holds the moved pose at it (it once kept 0.5236 rad where joint_states
// said 1.0).
TEST(ResetsPausedClock, TfAtTheMovedStampIsTheMovedPose) {
  ros::NodeHandle nh;
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  Recorder<MechanismState> state(nh, "mechanism_state");
  Recorder<ResetEvent> events(nh, "kane_sim/reset_event");
  ASSERT_TRUE(state.waitForCount(1, 20.0));
  ASSERT_TRUE(test::waitFor([&] { return events.connected(); }, 10.0));
  const ros::Time before = state.last().header.stamp;
  const auto lookup = [&](const ros::Time& at, geometry_msgs::TransformStamped* out) {
    return test::waitFor(
        [&] {
          try {
            *out = buffer.lookupTransform("mechanism", "rod1", at);
            return true;
          } catch (const tf2::TransformException&) {
            return false;
          }
        },
        5.0);
  };
  SetState set;
  set.request.q1 = 1.0;
  set.request.spring_at_rest = true;
  ASSERT_TRUE(ros::service::waitForService("kane_sim/set_state", ros::Duration(10.0)));
  ASSERT_TRUE(ros::service::call("kane_sim/set_state", set));
  ASSERT_TRUE(set.response.success) << set.response.message;
  ASSERT_TRUE(events.waitForCount(1, 5.0));
  const ros::Time moved = events.messages()[0].header.stamp;
  EXPECT_GT(moved, before);
  geometry_msgs::TransformStamped rod1;
  ASSERT_TRUE(lookup(moved, &rod1));
  EXPECT_NEAR(rod1Angle(rod1), 1.0, 1e-9);
  EXPECT_EQ(rod1.header.stamp, moved);

  std_srvs::Empty empty;
  ASSERT_TRUE(ros::service::call("kane_sim/reset", empty));
  ASSERT_TRUE(events.waitForCount(2, 5.0));
  const ros::Time reset = events.messages()[1].header.stamp;
  EXPECT_GT(reset, moved);
  ASSERT_TRUE(lookup(reset, &rod1));
  EXPECT_NEAR(rod1Angle(rod1), M_PI / 6, 1e-9);
  // Sim time itself stood still through both.
  EXPECT_EQ(events.messages()[0].sim_time, events.messages()[1].sim_time);
}

}  // namespace
}  // namespace kane_sim
