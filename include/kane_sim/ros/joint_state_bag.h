// Reads a bag's sensor_msgs/JointState topic (and the node's ~input_log) into columns, in C++:
// identify reads rigs' bags of an hour at 1 kHz (3.6 million messages), which rosbag's Python
// reader takes minutes and gigabytes over (its index alone is a Python object per message). The
// Python module kane_sim._bag is this, translated.
#ifndef KANE_SIM_ROS_JOINT_STATE_BAG_H
#define KANE_SIM_ROS_JOINT_STATE_BAG_H

#include <algorithm>
#include <cstddef>
#include <cstdint>
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
// joints' positions, velocities and the first joint's effort.
struct JointStateColumns {
  std::vector<double> t, position_a, position_b, velocity_a, velocity_b, effort_a;
  bool has_velocity = true;  // every row has both joints' velocities
  // 1 where that row's message has them (else 0); empty when every row has them
  std::vector<std::uint8_t> velocity_rows;
  bool anyVelocity() const {  // some row has both joints' velocities
    return has_velocity ||
           std::find(velocity_rows.begin(), velocity_rows.end(), 1) != velocity_rows.end();
  }
  std::size_t unstamped = 0;  // messages whose header stamp is 0 (then t is the bag's times)
  std::size_t skipped = 0;    // unusable messages left out (UnusableMessages::kSkip)
  std::vector<std::string> skip_notes;  // the first of them, each named
};

// What to do with a message that lacks a joint, the effort or the positions: stop the read
// (identify: a recording with holes is not fitted), or leave it out, count it and name the first
// ones (the observer: another publisher's messages interleaved on the topic, as the node skips
// them).
enum class UnusableMessages { kStop, kSkip };

// Reads `topic` of `path` for joints `a` (with its effort) and `b`. Throws BagReadError for a
// message without either joint, without a's effort or without positions (naming the message's
// index; with kSkip only when no message is usable), for a message rosbag cannot read (a corrupt
// chunk), and for a topic with no messages.
// `interrupted` (when set) is asked every 65536 messages: true stops the read (BagReadError
// "interrupted").
JointStateColumns readJointStates(const std::string& path, const std::string& topic,
                                  const std::string& a, const std::string& b,
                                  const std::function<bool()>& interrupted = {},
                                  UnusableMessages unusable = UnusableMessages::kStop);

// A node's ~input_log (kane_sim/InputLog) as columns, one row per logged input in the bag's
// order: what identify needs to drive its replays with the commands as the node applied them
// (held from the tick each arrived at) instead of guessing them from effort samples.
struct InputLogColumns {
  std::vector<double> t;            // header stamps [s]: the clock of the node's joint_states
  std::vector<std::uint64_t> seq;   // the node's numbering: a gap is an input not recorded
  std::vector<std::uint64_t> tick;  // the physics tick the input took effect at
  std::vector<std::uint8_t> kind;   // InputLog::TORQUE, SETPOINT, RESET or SET_STATE
  std::vector<double> value;        // the torque [N m] or setpoint as received (NaN kept)
};

// Reads `topic` (kane_sim/InputLog) of `path`. Throws BagReadError for a topic with no messages
// or of another type, and for a message rosbag cannot read. `interrupted` as readJointStates'.
InputLogColumns readInputLog(const std::string& path, const std::string& topic,
                             const std::function<bool()>& interrupted = {});

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_JOINT_STATE_BAG_H
