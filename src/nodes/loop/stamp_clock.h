// The node's stamps: sim time on the sim epoch in /clock mode; else wall time, held monotonic
// when the system clock steps back (tf drops stamps that go backwards). Also whether
// /use_sim_time agrees with the mode, said once per disagreement. ROS-thin: ros::Time only,
// no master, so it is unit-tested alone.
#ifndef KANE_SIM_NODES_LOOP_STAMP_CLOCK_H
#define KANE_SIM_NODES_LOOP_STAMP_CLOCK_H

#include <string>

#include <ros/time.h>

namespace kane_sim {

class StampClock {
 public:
  explicit StampClock(bool sim_time) : sim_time_(sim_time) {}

  // The stamp for a message at sim time `sim_seconds`, the wall clock reading `wall`. In wall
  // mode a reading at or before the last stamp gives the last stamp + 1 µs; `clock_went_back`
  // (when given) is set to how far it went back [s], 0 otherwise.
  ros::Time stamp(double sim_seconds, const ros::WallTime& wall, double* clock_went_back = nullptr);
  ros::Time stamp(double sim_seconds) { return stamp(sim_seconds, ros::WallTime::now()); }

  // The next stamp comes after every stamp given so far, also in sim-time mode where the sim
  // time has not advanced (a moved state: reset, set_state): 1 µs past the last, so that tf
  // listeners take the moved pose at its own stamp instead of keeping the old one there.
  void forceNext() { force_next_ = true; }

  // A warning when /use_sim_time (`use_sim_time`) contradicts the mode, once until they agree
  // again; "" otherwise.
  std::string checkUseSimTime(bool use_sim_time);

  bool simTime() const { return sim_time_; }

 private:
  bool sim_time_;
  ros::Time last_wall_stamp_;
  ros::Time last_sim_stamp_;  // sim-time stamps never go back, nor repeat after forceNext
  bool force_next_ = false;
  bool warned_ = false;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_LOOP_STAMP_CLOCK_H
