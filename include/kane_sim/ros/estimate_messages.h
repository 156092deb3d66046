// The estimator (estimate/) at the ROS boundary: a JointState read as a rig's reading, the
// estimate as kane_sim/StateEstimate, the alarm as a /diagnostics status. Plain functions, as
// ros/messages.h; the observer node and `observer --bag` only call them.
#ifndef KANE_SIM_ROS_ESTIMATE_MESSAGES_H
#define KANE_SIM_ROS_ESTIMATE_MESSAGES_H

#include <string>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <ros/time.h>
#include <sensor_msgs/JointState.h>

#include "kane_sim/StateEstimate.h"
#include "kane_sim/estimate/estimate_table.h"
#include "kane_sim/estimate/mechanism_estimator.h"

namespace kane_sim {

// crank_joint's and slider4_joint's positions, crank_joint's effort (the delivered torque) and
// both velocities when the message carries them; stamp from the header, or `receipt` when the
// header's is zero. False, with `why` naming what is missing, otherwise. Values are not judged
// here: the estimator refuses what is not finite, naming it.
bool rigReading(const sensor_msgs::JointState& msg, const ros::Time& receipt, RigReading* reading,
                std::string* why);

kane_sim::StateEstimate stateEstimateMessage(const EstimateRow& row,
                                             const MechanismEstimator& estimator,
                                             const ros::Time& stamp);

// The alarm as /diagnostics shows it: level, message, and the window's numbers as values.
// `silence` [s]: how long since the last usable reading arrived; longer than the estimator's
// restart_gap once it has started is a WARN of its own (the rig or its driver stopped: the
// estimate is that old), whatever the last window said.
diagnostic_msgs::DiagnosticStatus estimatorStatus(const MechanismEstimator& estimator,
                                                  const std::string& name, double silence = 0.0);

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_ESTIMATE_MESSAGES_H
