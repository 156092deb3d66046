// A JointState topic of a bag into columns: rosbag's C++ view, one message at a time.
#include "kane_sim/ros/joint_state_bag.h"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/JointState.h>

#include "kane_sim/InputLog.h"

namespace kane_sim {

namespace {

rosbag::Bag openForReading(const std::string& path) {
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {  // rosbag::BagException and its kin on garbage
    throw BagReadError(path + " is not a readable bag: " + e.what() +
                       " (truncated or not a bag; a recording cut short is repaired by `rosbag "
                       "reindex`)");
  }
  return bag;
}

// Either spelling of a topic: a bag written by rosbag's Python API may hold "joint_states" for
// "/joint_states".
std::vector<std::string> bothSpellings(const std::string& topic) {
  return {topic, !topic.empty() && topic[0] == '/' ? topic.substr(1) : "/" + topic};
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

}  // namespace

std::map<std::string, std::string> bagTopicTypes(const std::string& path) {
  rosbag::Bag bag = openForReading(path);
  rosbag::View view(bag);  // its queries are not const
  std::map<std::string, std::string> out;
  for (const rosbag::ConnectionInfo* c : view.getConnections()) out[c->topic] = c->datatype;
  return out;
}

JointStateColumns readJointStates(const std::string& path, const std::string& topic,
                                  const std::string& a, const std::string& b,
                                  const std::function<bool()>& interrupted,
                                  UnusableMessages unusable) {
  rosbag::Bag bag = openForReading(path);
  rosbag::View view(bag, rosbag::TopicQuery(bothSpellings(topic)));
  JointStateColumns out;
  const std::size_t count = view.size();
  for (std::vector<double>* column :
       {&out.t, &out.position_a, &out.position_b, &out.velocity_a, &out.velocity_b, &out.effort_a})
    column->reserve(count);
  out.velocity_rows.reserve(count);
  constexpr std::size_t kMaxSkipNotes = 10;
  const std::string where = path + " on " + topic;
  std::vector<double> received;  // the bag's times, for when a header has no stamp
  received.reserve(count);
  std::size_t read = 0;
  try {
    for (const rosbag::MessageInstance& m : view) {
      if ((++read & 0xFFFF) == 0 && interrupted && interrupted()) throw BagReadError("interrupted");
      const sensor_msgs::JointState::ConstPtr msg = m.instantiate<sensor_msgs::JointState>();
      if (!msg) throw BagReadError(where + " is not sensor_msgs/JointState");
      const std::string which = where + ", message " + std::to_string(read - 1) + ",";
      std::size_t i = msg->name.size(), j = msg->name.size();
      std::string lacks;
      for (std::size_t k = 0; k < msg->name.size(); ++k) {
        for (const auto& [index, joint] : {std::pair{&i, &a}, std::pair{&j, &b}}) {
          if (msg->name[k] != *joint) continue;
          if (*index != msg->name.size() && lacks.empty())
            lacks = which + " names '" + *joint + "' twice: which value is the joint's?";
          *index = k;
        }
      }
      for (const auto& [index, joint] : {std::pair{i, &a}, std::pair{j, &b}})
        if (lacks.empty() && index == msg->name.size())
          lacks = which + " has no joint '" + *joint + "' (names: " + joined(msg->name) + ")";
      if (lacks.empty() && msg->effort.size() <= i)
        lacks = which + " carries no effort for " + a + ": the delivered torque is needed";
      if (lacks.empty() && msg->position.size() <= std::max(i, j))
        lacks = which + " carries no positions";
      if (!lacks.empty()) {
        if (unusable == UnusableMessages::kStop) throw BagReadError(lacks);
        if (out.skip_notes.size() < kMaxSkipNotes) out.skip_notes.push_back(lacks);
        ++out.skipped;
        continue;
      }
      const bool velocities = msg->velocity.size() > std::max(i, j);
      out.has_velocity = out.has_velocity && velocities;
      out.velocity_rows.push_back(velocities ? 1 : 0);
      const double stamp = msg->header.stamp.toSec();
      if (stamp == 0.0) ++out.unstamped;
      out.t.push_back(stamp);
      received.push_back(m.getTime().toSec());
      out.position_a.push_back(msg->position[i]);
      out.position_b.push_back(msg->position[j]);
      out.velocity_a.push_back(velocities ? msg->velocity[i] : 0.0);
      out.velocity_b.push_back(velocities ? msg->velocity[j] : 0.0);
      out.effort_a.push_back(msg->effort[i]);
    }
  } catch (const BagReadError&) {
    throw;
  } catch (const std::exception& e) {  // rosbag's and the deserializer's, on a corrupt chunk
    throw BagReadError(path + " is not a readable bag: " + e.what() + " (after " +
                       std::to_string(read) + " messages of " + topic + "; a corrupt chunk)");
  }
  if (out.unstamped > 0) out.t = std::move(received);
  if (out.t.empty() && out.skipped > 0)
    throw BagReadError(path + " has no usable message on " + topic + " (" +
                       std::to_string(out.skipped) +
                       " unusable; the first: " + out.skip_notes.front() + ")");
  if (out.t.empty()) throw BagReadError(path + " has no messages on " + topic);
  if (out.has_velocity) out.velocity_rows.clear();  // every row: no mask needed
  return out;
}

InputLogColumns readInputLog(const std::string& path, const std::string& topic,
                             const std::function<bool()>& interrupted) {
  rosbag::Bag bag = openForReading(path);
  rosbag::View view(bag, rosbag::TopicQuery(bothSpellings(topic)));
  InputLogColumns out;
  std::size_t read = 0;
  try {
    for (const rosbag::MessageInstance& m : view) {
      if ((++read & 0xFFFF) == 0 && interrupted && interrupted()) throw BagReadError("interrupted");
      const kane_sim::InputLog::ConstPtr msg = m.instantiate<kane_sim::InputLog>();
      if (!msg) throw BagReadError(path + " on " + topic + " is not kane_sim/InputLog");
      out.t.push_back(msg->header.stamp.toSec());
      out.seq.push_back(msg->seq);
      out.tick.push_back(msg->tick);
      out.kind.push_back(msg->kind);
      out.value.push_back(msg->value);
    }
  } catch (const BagReadError&) {
    throw;
  } catch (const std::exception& e) {  // rosbag's and the deserializer's, on a corrupt chunk
    throw BagReadError(path + " is not a readable bag: " + e.what() + " (after " +
                       std::to_string(read) + " messages of " + topic + "; a corrupt chunk)");
  }
  if (out.t.empty()) throw BagReadError(path + " has no messages on " + topic);
  return out;
}

}  // namespace kane_sim
