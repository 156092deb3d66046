// A controller in the loop, offline, as the node runs one in lockstep (simulation.lockstep): each
// reading joint_states would carry is answered before the next physics step — with the sensors
// on, every reading as it arrives (after the step it is due at), stamped at its arrival; with
// them off, the true joints at every publish tick, before the steps that follow. The answer is a
// torque_command (SimDriver::command); no answer leaves the last in force. The node in lockstep
// gives the same states bit for bit (test/node/test_tracking.cpp). ROS-free.
#ifndef KANE_SIM_SIM_CLOSED_LOOP_H
#define KANE_SIM_SIM_CLOSED_LOOP_H

#include <cstdint>
#include <functional>
#include <optional>

#include "kane_sim/description/joint_values.h"
#include "kane_sim/sim/sim_driver.h"

namespace kane_sim {

// A reading (its stamp [ns], as a message carries it: stampNanoseconds, and the joints as
// measured) -> the torque to command, or none.
using ReadingController =
    std::function<std::optional<double>(std::int64_t stamp, const JointValues&)>;

// Sim time t [s] in whole nanoseconds, rounded as ros::Duration(t) rounds it: the node's stamp
// of t, less the epoch it adds (ros/messages.h).
std::int64_t stampNanoseconds(double t);

// Steps `driver` until its time reaches `until` [s], `controller` answering every reading;
// `after_step` is called after each step (may be empty). False when a step was refused (the
// driver keeps its last good state) or `after_step` returned false.
bool runClosedLoop(SimDriver& driver, double until, const ReadingController& controller,
                   const std::function<bool(const SimDriver&)>& after_step);

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_CLOSED_LOOP_H
