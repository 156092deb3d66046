// Reads a bag's sensor_msgs/JointState topic into columns, in C++: identify reads rigs' bags of
// an hour at 1 kHz (3.6 million messages), which rosbag's Python reader takes minutes and
// gigabytes over (its index alone is a Python object per message). The Python module
// kane_sim._bag is this, translated.
#ifndef KANE_SIM_ROS_JOINT_STATE_BAG_H
#define KANE_SIM_ROS_JOINT_STATE_BAG_H

#include <cstddef>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace kane_sim {

// A bag that cannot be read as asked: the message names the bag, the topic and what is missing.
struct BagReadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Every topic of the bag with its message type ("sensor_msgs/JointState").
std::map<std::string, std::string> bagTopicTypes(const std::string& path);

// Two joints of a JointState topic, one row per message: t (the headers' stamps, or the bag's
// receive times for every message when any header has none: one clock, never two mixed), the
// joints' positions, velocities (when every message has them) and the first joint's effort.
struct JointStateColumns {
  std::vector<double> t, position_a, position_b, velocity_a, velocity_b, effort_a;
  bool has_velocity = true;
  std::size_t unstamped = 0;  // messages whose header stamp is 0 (then t is the bag's times)
};

// Reads `topic` of `path` for joints `a` (with its effort) and `b`. Throws BagReadError for a
// message without either joint, without a's effort or without positions (naming the message's
// index), for a message rosbag cannot read (a corrupt chunk), and for a topic with no messages.
// `interrupted` (when set) is asked every 65536 messages: true stops the read (BagReadError
// "interrupted").
JointStateColumns readJointStates(const std::string& path, const std::string& topic,
                                  const std::string& a, const std::string& b,
                                  const std::function<bool()>& interrupted = {});

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_JOINT_STATE_BAG_H
