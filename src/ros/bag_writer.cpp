#include "kane_sim/ros/bag_writer.h"

#include <rosgraph_msgs/Clock.h>
#include <boost/make_shared.hpp>

#include <memory>

namespace kane_sim {

// rosbag::Bag's destructor closes an open file again, and throws from there when the disk is
// full, which ends the process. After any failed operation the Bag is therefore abandoned
// (deliberately not destroyed): the caller reports the error and exits.
template <typename Operation>
void BagWriter::guarded(Operation operation) {
  try {
    operation(*bag_);
  } catch (...) {
    static_cast<void>(bag_.release());  // abandoned, see above
    throw;
  }
}

BagWriter::BagWriter(const std::string& path) : bag_(std::make_unique<rosbag::Bag>()) {
  guarded([&path](rosbag::Bag& bag) { bag.open(path, rosbag::bagmode::Write); });
}

BagWriter::~BagWriter() {
  // A destructor must not throw (a failed close was already reported by an explicit close()).
  try {
    close();
  } catch (const std::exception&) {
  }
}

void BagWriter::writeStatic(const std::vector<geometry_msgs::TransformStamped>& transforms) {
  if (transforms.empty()) return;
  tf2_msgs::TFMessage msg;
  msg.transforms = transforms;
  // rosbag play republishes latched topics as latched: late subscribers (rviz) still get it.
  // A given connection header is written verbatim, so it must carry the message's identity too.
  auto header = boost::make_shared<ros::M_string>();
  (*header)["callerid"] = "/kane_sim";
  (*header)["latching"] = "1";
  (*header)["type"] = ros::message_traits::datatype<tf2_msgs::TFMessage>();
  (*header)["md5sum"] = ros::message_traits::md5sum<tf2_msgs::TFMessage>();
  (*header)["message_definition"] = ros::message_traits::definition<tf2_msgs::TFMessage>();
  guarded([&](rosbag::Bag& bag) {
    bag.write("/tf_static", transforms.front().header.stamp, msg, header);
  });
}

void BagWriter::write(const PublishedMessages& m, const ros::Time& stamp, bool sensors_enabled) {
  rosgraph_msgs::Clock clock;
  clock.clock = stamp;
  const std::string joint_states = std::string("/") + truthJointStatesTopic(sensors_enabled);
  guarded([&](rosbag::Bag& bag) {
    bag.write("/clock", stamp, clock);
    bag.write(joint_states, stamp, m.joint_state);
    bag.write("/tf", stamp, m.tf);
    bag.write("/mechanism_state", stamp, m.mechanism_state);
    bag.write("/visualization_markers", stamp, m.markers);
  });
}

void BagWriter::writeServoState(const kane_sim::ServoState& state) {
  guarded([&](rosbag::Bag& bag) { bag.write("/servo_state", state.header.stamp, state); });
}

void BagWriter::writeInputLog(const kane_sim::InputLog& input) {
  guarded([&](rosbag::Bag& bag) { bag.write("/kane_sim/input_log", input.header.stamp, input); });
}

void BagWriter::writeSensorReading(const sensor_msgs::JointState& reading) {
  const std::string topic = std::string("/") + kJointStatesTopic;
  guarded([&](rosbag::Bag& bag) { bag.write(topic, reading.header.stamp, reading); });
}

void BagWriter::close() {
  if (bag_ && bag_->isOpen()) guarded([](rosbag::Bag& bag) { bag.close(); });
}

}  // namespace kane_sim
