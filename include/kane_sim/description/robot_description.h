// The mechanism as a robot tree: links with their inertial data and shapes, joints with the
// names and conventions of joint_states. One description, built from the loaded config, feeds
// the URDF (robot_description), the tf frames the node and `simulate --bag` publish, and so
// what robot_state_publisher computes from the URDF and joint_states is the same tree.
//
// URDF holds trees only: the loop O-A-B (rod 2 pinned to slider 3 at B) is closed in the
// physics, not here. Rod 2 hangs from rod 1 (coupler_joint) and slider 3 runs on the rail
// (slider3_joint); joint_states gives both the values that close the loop.
//
//   world --world_joint (fixed)--> mechanism --crank_joint (q1)--> rod1 --coupler_joint (-2 q1)-->
//   rod2
//                                            --slider3_joint (4 L cos q1)--> slider3
//                                            --slider4_joint (q2)--> slider4
#ifndef KANE_SIM_DESCRIPTION_ROBOT_DESCRIPTION_H
#define KANE_SIM_DESCRIPTION_ROBOT_DESCRIPTION_H

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "kane_sim/config/config.h"
#include "kane_sim/config/frame_names.h"
#include "kane_sim/description/joint_values.h"

namespace kane_sim {

// A URDF <origin>: translation, then fixed-axis roll-pitch-yaw (R = Rz(yaw) Ry(pitch) Rx(roll)).
struct UrdfOrigin {
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();
  Eigen::Isometry3d transform() const;
};

struct LinkInertial {
  UrdfOrigin origin;                                            // the mass center in the link frame
  double mass = 0.0;                                            // [kg]
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Zero();  // ixx, iyy, izz [kg m^2]
};

struct LinkShape {
  enum class Kind { kCylinder, kBox };
  Kind kind = Kind::kBox;
  UrdfOrigin origin;
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();  // kBox
  double radius = 0.0;                                 // kCylinder, axis along the shape's z
  double length = 0.0;                                 // kCylinder
  std::string material;                                // a name in RobotDescription::materials
};

struct LinkDescription {
  std::string name;
  std::optional<LinkInertial> inertial;
  std::optional<LinkShape> shape;  // visual and collision
};

struct JointDescription {
  enum class Type { kFixed, kContinuous, kPrismatic };
  std::string name;
  Type type = Type::kFixed;
  std::string parent;
  std::string child;
  UrdfOrigin origin;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  int joint_index = -1;             // into JointValues (kCrankJoint ...); -1 for fixed joints
  double lower = 0.0, upper = 0.0;  // kPrismatic travel [m]
  std::string mimic;                // the joint this one follows, "" for none
  double mimic_multiplier = 1.0;

  // parent -> child at this joint position (rad or m; ignored for fixed joints).
  Eigen::Isometry3d transform(double position) const;
};

struct MaterialColor {
  std::string name;
  double r, g, b;
};

struct RobotDescription {
  std::string name;
  FrameNames frames;
  std::vector<MaterialColor> materials;
  std::vector<LinkDescription> links;
  std::vector<JointDescription> joints;
};

// Built from the config's mechanism parameters and frame settings.
RobotDescription describeRobot(const Config& config);

// parent -> child of one joint at the positions in `joints`, as the tf tree carries it.
struct JointPose {
  const JointDescription* joint;
  Eigen::Isometry3d parent_to_child;
};
std::vector<JointPose> fixedJointPoses(const RobotDescription& robot);
std::vector<JointPose> movingJointPoses(const RobotDescription& robot, const JointValues& joints);

}  // namespace kane_sim

#endif  // KANE_SIM_DESCRIPTION_ROBOT_DESCRIPTION_H
