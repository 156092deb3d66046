#include "kane_sim/ros/bag_writer.h"

#include <rosgraph_msgs/Clock.h>
#include <boost/make_shared.hpp>

namespace kane_sim {

BagWriter::BagWriter(const std::string& path) { bag_.open(path, rosbag::bagmode::Write); }

BagWriter::~BagWriter() { close(); }

void BagWriter::writeStatic(const geometry_msgs::TransformStamped& world_to_mechanism) {
  tf2_msgs::TFMessage msg;
  msg.transforms.push_back(world_to_mechanism);
  // rosbag play republishes latched topics as latched: late subscribers (rviz) still get it.
  // A given connection header is written verbatim, so it must carry the message's identity too.
  auto header = boost::make_shared<ros::M_string>();
  (*header)["callerid"] = "/kane_sim";
  (*header)["latching"] = "1";
  (*header)["type"] = ros::message_traits::datatype<tf2_msgs::TFMessage>();
  (*header)["md5sum"] = ros::message_traits::md5sum<tf2_msgs::TFMessage>();
  (*header)["message_definition"] = ros::message_traits::definition<tf2_msgs::TFMessage>();
  bag_.write("/tf_static", world_to_mechanism.header.stamp, msg, header);
}

void BagWriter::write(const PublishedMessages& m, const ros::Time& stamp) {
  rosgraph_msgs::Clock clock;
  clock.clock = stamp;
  bag_.write("/clock", stamp, clock);
  bag_.write("/joint_states", stamp, m.joint_state);
  bag_.write("/tf", stamp, m.tf);
  bag_.write("/mechanism_state", stamp, m.mechanism_state);
  bag_.write("/visualization_markers", stamp, m.markers);
}

void BagWriter::close() {
  if (bag_.isOpen()) bag_.close();
}

}  // namespace kane_sim
