#include "kane_sim/sim/checkpoint.h"

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <vector>

namespace kane_sim {
namespace {

constexpr const char* kHeader = "kane_sim checkpoint 1";
// 10^5 readings in flight of ~400 bytes each, and the rest: anything larger is not a driver's.
constexpr size_t kMaxCheckpointBytes = 64u << 20;

// The field names a checkpoint holds (delayedN and readingN numbered from 0).
bool known(const std::string& name) {
  static const char* const fixed[] = {"state",
                                      "ticks",
                                      "torque",
                                      "ledger",
                                      "counts",
                                      "flags",
                                      "dopri5_substep",
                                      "command",
                                      "delayed_commands",
                                      "setpoint",
                                      "servo",
                                      "sensors_random",
                                      "sensors_bias",
                                      "sensors_last_delivery",
                                      "readings"};
  for (const char* f : fixed)
    if (name == f) return true;
  for (const char* prefix : {"delayed", "reading"}) {
    const std::string p = prefix;
    if (name.size() > p.size() && name.compare(0, p.size(), p) == 0 &&
        name.find_first_not_of("0123456789", p.size()) == std::string::npos)
      return true;
  }
  return false;
}

std::string hex(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%a", v);
  return buffer;
}

// One "name value value ..." line per field.
class Writer {
 public:
  Writer() { out_ << kHeader << "\n"; }
  template <typename... Values>
  void line(const std::string& name, Values... values) {
    out_ << name;
    (put(values), ...);
    out_ << "\n";
  }
  void raw(const std::string& name, const std::string& text) {
    out_ << name << ' ' << text << "\n";
  }
  std::string text() const { return out_.str(); }

 private:
  void put(double v) { out_ << ' ' << hex(v); }
  void put(std::uint64_t v) { out_ << ' ' << v; }
  void put(bool v) { out_ << ' ' << (v ? 1 : 0); }
  std::ostringstream out_;
};

class Reader {
 public:
  explicit Reader(const std::string& text) {
    std::istringstream in(text);
    std::string header;
    std::getline(in, header);
    if (header != kHeader)
      throw CheckpointError("not a kane_sim checkpoint (its first line is '" +
                            header.substr(0, 40) + "', expected '" + kHeader + "')");
    if (text.size() > kMaxCheckpointBytes)
      throw CheckpointError("a checkpoint of " + std::to_string(text.size()) +
                            " bytes is larger than any driver's (" +
                            std::to_string(kMaxCheckpointBytes) + ")");
    for (std::string line; std::getline(in, line);) {
      const size_t space = line.find(' ');
      const std::string name = line.substr(0, space);
      if (name.empty()) continue;
      if (!known(name))
        throw CheckpointError("checkpoint field '" + name.substr(0, 40) +
                              "' is not one of a kane_sim checkpoint's");
      if (!lines_.emplace(name, space == std::string::npos ? "" : line.substr(space + 1)).second)
        throw CheckpointError("checkpoint field '" + name + "' appears twice");
    }
  }
  // The field's values, `count` of them (any number when count < 0).
  std::vector<std::string> fields(const std::string& name, int count) const {
    const auto it = lines_.find(name);
    if (it == lines_.end()) throw CheckpointError("checkpoint field '" + name + "' is missing");
    std::istringstream in(it->second);
    std::vector<std::string> out;
    for (std::string f; in >> f;) out.push_back(f);
    if (count >= 0 && static_cast<int>(out.size()) != count)
      throw CheckpointError("checkpoint field '" + name + "' has " + std::to_string(out.size()) +
                            " values, expected " + std::to_string(count));
    return out;
  }
  const std::string& raw(const std::string& name) const {
    const auto it = lines_.find(name);
    if (it == lines_.end()) throw CheckpointError("checkpoint field '" + name + "' is missing");
    return it->second;
  }
  static double number(const std::string& name, const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0')
      throw CheckpointError("checkpoint field '" + name + "': '" + text + "' is not a number");
    return v;
  }
  static std::uint64_t count(const std::string& name, const std::string& text) {
    char* end = nullptr;
    const std::uint64_t v = std::strtoull(text.c_str(), &end, 10);
    if (end == text.c_str() || *end != '\0' || text[0] == '-')
      throw CheckpointError("checkpoint field '" + name + "': '" + text +
                            "' is not a whole number >= 0");
    return v;
  }
  double number(const std::string& name) const { return number(name, fields(name, 1)[0]); }
  std::uint64_t count(const std::string& name) const { return count(name, fields(name, 1)[0]); }
  bool flag(const std::string& name) const {
    const std::string v = fields(name, 1)[0];
    if (v != "0" && v != "1")
      throw CheckpointError("checkpoint field '" + name + "': '" + v + "' is not 0 or 1");
    return v == "1";
  }

 private:
  std::map<std::string, std::string> lines_;
};

}  // namespace

std::string checkpointText(const DriverCheckpoint& c) {
  Writer w;
  const Simulator::Dynamics& d = c.simulator;
  w.line("state", d.state.q1, d.state.q2, d.state.u1, d.state.u2);
  w.line("ticks", d.ticks);
  w.line("torque", d.torque);
  w.line("ledger", d.motor_work, d.dissipated_energy, d.impact_energy, d.parameter_energy);
  w.line("counts", d.slider_crossings, d.contact_impacts, d.parameter_changes);
  w.line("flags", d.step_too_coarse, d.slider4_below, d.resting_contact);
  w.line("dopri5_substep", d.dopri5_substep);
  const TorqueCommand::Memory& m = c.command;
  w.line("command", m.commanded, m.clamped, m.last_command_time, m.have_command, m.timed_out);
  w.line("delayed_commands", static_cast<std::uint64_t>(c.delayed_commands.size()));
  for (size_t i = 0; i < c.delayed_commands.size(); ++i)
    w.line("delayed" + std::to_string(i), c.delayed_commands[i].due_tick,
           c.delayed_commands[i].torque);
  w.line("setpoint", c.setpoint);
  const ServoStatus& s = c.servo_status;
  w.line("servo", c.servo_integral, s.setpoint, s.measured, s.error, s.proportional, s.integral,
         s.derivative, s.feedforward, s.output, s.command, s.saturated);
  const JointSensors::Memory& js = c.sensors;
  w.raw("sensors_random", js.random);  // the standard library's own text of engine and normal
  w.line("sensors_bias", js.bias[0], js.bias[1], js.bias[2], js.bias[3]);
  w.line("sensors_last_delivery", js.last_delivery_tick);
  w.line("readings", static_cast<std::uint64_t>(js.queue.size()));
  for (size_t i = 0; i < js.queue.size(); ++i) {
    const SensorReading& r = js.queue[i];
    const JointValues& j = r.joints;
    w.line("reading" + std::to_string(i), r.sample_tick, r.delivery_tick, r.sample_time,
           j.position[0], j.position[1], j.position[2], j.position[3], j.velocity[0], j.velocity[1],
           j.velocity[2], j.velocity[3], j.effort[0], j.effort[1], j.effort[2], j.effort[3]);
  }
  return w.text();
}

DriverCheckpoint parseCheckpoint(const std::string& text) {
  const Reader r(text);
  DriverCheckpoint c;
  const auto numbers = [&r](const std::string& name, int count) {
    std::vector<double> out;
    for (const std::string& f : r.fields(name, count)) out.push_back(Reader::number(name, f));
    return out;
  };
  Simulator::Dynamics& d = c.simulator;
  const auto x = numbers("state", 4);
  d.state = State{x[0], x[1], x[2], x[3]};
  d.ticks = r.count("ticks");
  d.torque = r.number("torque");
  const auto ledger = numbers("ledger", 4);
  d.motor_work = ledger[0], d.dissipated_energy = ledger[1], d.impact_energy = ledger[2],
  d.parameter_energy = ledger[3];
  const auto counts = r.fields("counts", 3);
  d.slider_crossings = Reader::count("counts", counts[0]);
  d.contact_impacts = Reader::count("counts", counts[1]);
  d.parameter_changes = Reader::count("counts", counts[2]);
  const auto flags = r.fields("flags", 3);
  for (const std::string& f : flags)
    if (f != "0" && f != "1")
      throw CheckpointError("checkpoint field 'flags': '" + f + "' is not 0 or 1");
  d.step_too_coarse = flags[0] == "1", d.slider4_below = flags[1] == "1",
  d.resting_contact = flags[2] == "1";
  d.dopri5_substep = r.number("dopri5_substep");
  const auto command = r.fields("command", 5);
  c.command.commanded = Reader::number("command", command[0]);
  c.command.clamped = Reader::number("command", command[1]);
  c.command.last_command_time = Reader::number("command", command[2]);
  c.command.have_command = command[3] == "1";
  c.command.timed_out = command[4] == "1";
  const std::uint64_t delayed = r.count("delayed_commands");
  if (delayed > 1000000) throw CheckpointError("checkpoint field 'delayed_commands' is too large");
  for (std::uint64_t i = 0; i < delayed; ++i) {
    const std::string name = "delayed" + std::to_string(i);
    const auto f = r.fields(name, 2);
    c.delayed_commands.push_back({Reader::count(name, f[0]), Reader::number(name, f[1])});
  }
  c.setpoint = r.number("setpoint");
  const auto servo = numbers("servo", 11);
  c.servo_integral = servo[0];
  ServoStatus& s = c.servo_status;
  s.setpoint = servo[1], s.measured = servo[2], s.error = servo[3], s.proportional = servo[4];
  s.integral = servo[5], s.derivative = servo[6], s.feedforward = servo[7], s.output = servo[8];
  s.command = servo[9], s.saturated = servo[10] != 0.0;
  c.sensors.random = r.raw("sensors_random");
  const auto bias = numbers("sensors_bias", 4);
  for (int j = 0; j < kNumJoints; ++j) c.sensors.bias[j] = bias[j];
  c.sensors.last_delivery_tick = r.count("sensors_last_delivery");
  const std::uint64_t readings = r.count("readings");
  if (readings > kMaxReadingsInFlight)
    throw CheckpointError(
        "checkpoint field 'readings' is larger than the readings in flight "
        "a config may hold");
  for (std::uint64_t i = 0; i < readings; ++i) {
    const std::string name = "reading" + std::to_string(i);
    const auto f = r.fields(name, 15);
    SensorReading reading;
    reading.sample_tick = Reader::count(name, f[0]);
    reading.delivery_tick = Reader::count(name, f[1]);
    reading.sample_time = Reader::number(name, f[2]);
    for (int j = 0; j < kNumJoints; ++j) {
      reading.joints.position[j] = Reader::number(name, f[3 + j]);
      reading.joints.velocity[j] = Reader::number(name, f[7 + j]);
      reading.joints.effort[j] = Reader::number(name, f[11 + j]);
    }
    c.sensors.queue.push_back(reading);
  }
  return c;
}

}  // namespace kane_sim
