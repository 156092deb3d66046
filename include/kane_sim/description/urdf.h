// The robot description as URDF text: what the node puts on `robot_description` and
// `rosrun kane_sim config_info urdf` prints.
#ifndef KANE_SIM_DESCRIPTION_URDF_H
#define KANE_SIM_DESCRIPTION_URDF_H

#include <string>

#include "kane_sim/description/robot_description.h"

namespace kane_sim {

std::string toUrdf(const RobotDescription& robot);

}  // namespace kane_sim

#endif  // KANE_SIM_DESCRIPTION_URDF_H
