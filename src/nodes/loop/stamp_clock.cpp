#include "loop/stamp_clock.h"

#include "kane_sim/ros/messages.h"

namespace kane_sim {

ros::Time StampClock::stamp(double sim_seconds, const ros::WallTime& wall,
                            double* clock_went_back) {
  if (clock_went_back) *clock_went_back = 0.0;
  if (sim_time_) {
    ros::Time t = simStamp(sim_seconds);
    const ros::Time after_last = last_sim_stamp_ + ros::Duration(0, force_next_ ? 1000 : 0);
    if (t < after_last) t = after_last;
    force_next_ = false;
    last_sim_stamp_ = t;
    return t;
  }
  // Wall-clock mode stamps wall time itself: ros::Time::now() would read a /clock that a
  // leftover /use_sim_time asks for (0 without one).
  ros::Time now(wall.sec, wall.nsec);
  force_next_ = false;  // wall stamps always move on
  if (now <= last_wall_stamp_) {
    if (clock_went_back) *clock_went_back = (last_wall_stamp_ - now).toSec();
    now = last_wall_stamp_ + ros::Duration(0, 1000);
  }
  last_wall_stamp_ = now;
  return now;
}

std::string StampClock::checkUseSimTime(bool use_sim_time) {
  if (use_sim_time == sim_time_) {
    warned_ = false;
    return "";
  }
  if (warned_) return "";
  warned_ = true;
  if (use_sim_time)
    return "/use_sim_time is true but this node runs on the wall clock (simulation/publish_clock "
           "false) and stamps wall time; other nodes wait for a /clock. Set /use_sim_time false "
           "(rosparam set /use_sim_time false) or publish_clock true";
  return "this node publishes /clock and stamps sim time, but /use_sim_time is false: other "
         "nodes will not follow its clock. Set /use_sim_time true before they start";
}

}  // namespace kane_sim
