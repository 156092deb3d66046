// The mechanism as the browser's page draws it: each link's shape (rods, sliders) from the robot
// description, posed by joint_states' values as the tf tree poses it, and projected onto the
// plane of motion. One robot model: rviz, the URDF and the page draw the same shapes.
#ifndef KANE_SIM_WEB_OUTLINES_H
#define KANE_SIM_WEB_OUTLINES_H

#include <string>
#include <vector>

#include <Eigen/Core>

#include "kane_sim/description/robot_description.h"

namespace kane_sim {
namespace web {

// A link's shape seen along the mechanism's z axis (the textbook's frame (0): x down, y across):
// its outline as a convex polygon in that frame's x-y plane [m], and its material's colour.
struct LinkOutline {
  std::string link;
  std::vector<Eigen::Vector2d> polygon;  // counter-clockwise in (x, y)
  double r = 0.0, g = 0.0, b = 0.0;
};

// Every link with a shape at joint positions `joints`, in the robot description's link order.
std::vector<LinkOutline> linkOutlines(const RobotDescription& robot, const JointValues& joints);

// Each link's frame origin in the mechanism frame [m] (x, y), in link order: where the page puts
// the spring's ends (slider3, slider4) and the torque's arrow (rod1 at O).
std::vector<std::pair<std::string, Eigen::Vector2d>> linkOrigins(const RobotDescription& robot,
                                                                 const JointValues& joints);

}  // namespace web
}  // namespace kane_sim

#endif  // KANE_SIM_WEB_OUTLINES_H
