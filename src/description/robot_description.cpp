#include "kane_sim/description/robot_description.h"

#include <cmath>

#include "kane_sim/description/body_shapes.h"

namespace kane_sim {
namespace {

UrdfOrigin at(double x, double y, double z, double roll = 0, double pitch = 0, double yaw = 0) {
  UrdfOrigin o;
  o.xyz = Eigen::Vector3d(x, y, z);
  o.rpy = Eigen::Vector3d(roll, pitch, yaw);
  return o;
}

MaterialColor material(const std::string& name, const float rgb[3]) {
  return {name, rgb[0], rgb[1], rgb[2]};
}

// A rod 2L long whose link frame sits at its inboard pin with x along the rod: mass center
// at (L, 0, 0). Slender: I about its own axis 0, I1z = I2z about the other two.
LinkDescription rodLink(const std::string& name, const MechanismParameters& p) {
  const double L = p.rod_half_length;
  LinkDescription link;
  link.name = name;
  link.inertial =
      LinkInertial{at(L, 0, 0), p.rod_mass, Eigen::Vector3d(0.0, p.rod_inertia, p.rod_inertia)};
  LinkShape rod;
  rod.kind = LinkShape::Kind::kCylinder;
  rod.origin = at(L, 0, 0, 0, M_PI / 2, 0);  // URDF cylinders run along z: turn z onto x
  rod.radius = shapes::kRodDiameter / 2;
  rod.length = 2 * L;
  rod.material = "rod";
  link.shape = rod;
  return link;
}

// A slider is a particle (mass, no rotational inertia) drawn as a box centred on its point.
LinkDescription sliderLink(const std::string& name, double mass) {
  LinkDescription link;
  link.name = name;
  link.inertial = LinkInertial{at(0, 0, 0), mass, Eigen::Vector3d::Zero()};
  LinkShape box;
  box.kind = LinkShape::Kind::kBox;
  box.box_size = Eigen::Vector3d(shapes::kSliderLength, shapes::kSliderWidth, shapes::kSliderDepth);
  box.material = "slider";
  link.shape = box;
  return link;
}

JointDescription joint(const std::string& name, JointDescription::Type type,
                       const std::string& parent, const std::string& child, UrdfOrigin origin,
                       const Eigen::Vector3d& axis, int index) {
  JointDescription j;
  j.name = name;
  j.type = type;
  j.parent = parent;
  j.child = child;
  j.origin = origin;
  j.axis = axis;
  j.joint_index = index;
  return j;
}

}  // namespace

Eigen::Isometry3d UrdfOrigin::transform() const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = xyz;
  t.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return t;
}

Eigen::Isometry3d JointDescription::transform(double position) const {
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  if (type == Type::kContinuous)
    motion.linear() = Eigen::AngleAxisd(position, axis).toRotationMatrix();
  else if (type == Type::kPrismatic)
    motion.translation() = position * axis;
  return origin.transform() * motion;
}

RobotDescription describeRobot(const Config& config) {
  const MechanismParameters& p = config.mechanism;
  const double L = p.rod_half_length;  // L
  RobotDescription robot{"kane_sim_mechanism", FrameNames(config.frames), {}, {}, {}};
  const FrameNames& f = robot.frames;
  robot.materials = {material("rod", MarkerColors::kRod),
                     material("slider", MarkerColors::kSlider)};

  robot.links = {LinkDescription{f.world, {}, {}},
                 LinkDescription{f.mechanism, {}, {}},
                 rodLink(f.bodies[kRod1], p),
                 rodLink(f.bodies[kRod2], p),
                 sliderLink(f.bodies[kSlider3], p.slider3_mass),
                 sliderLink(f.bodies[kSlider4], p.slider4_mass)};

  using Type = JointDescription::Type;
  const Eigen::Vector3d k = Eigen::Vector3d::UnitZ();  // out of the plane
  const Eigen::Vector3d i = Eigen::Vector3d::UnitX();  // the rail, down
  // world -> mechanism: O at pivot_height, +90 deg about world y turns the textbook's x (i) onto
  // world -z, so gravity points down in rviz (REP-103).
  JointDescription world_joint = joint("world_joint", Type::kFixed, f.world, f.mechanism,
                                       at(0, 0, config.frames.pivot_height, 0, M_PI / 2, 0), k, -1);
  // Rod 1 turns about O by q1 from i.
  JointDescription crank = joint(kJointNames[kCrankJoint], Type::kContinuous, f.mechanism,
                                 f.bodies[kRod1], at(0, 0, 0), k, kCrankJoint);
  // Rod 2 about A = (2L, 0, 0) in rod 1's frame, by -2 q1 relative to rod 1 (it turns at -u1).
  JointDescription coupler = joint(kJointNames[kCouplerJoint], Type::kContinuous, f.bodies[kRod1],
                                   f.bodies[kRod2], at(2 * L, 0, 0), k, kCouplerJoint);
  coupler.mimic = kJointNames[kCrankJoint];
  coupler.mimic_multiplier = -2.0;
  // Slider 3 at x_B = 4 L cos q1 on the rail, within [-4L, 4L].
  JointDescription slider3 = joint(kJointNames[kSlider3Joint], Type::kPrismatic, f.mechanism,
                                   f.bodies[kSlider3], at(0, 0, 0), i, kSlider3Joint);
  slider3.lower = -4 * L;
  slider3.upper = 4 * L;
  // Slider 4 at x_C = q2. The textbook example has no end stops: the travel written here is
  // only what URDF requires of a prismatic joint, far beyond any reachable position.
  JointDescription slider4 = joint(kJointNames[kSlider4Joint], Type::kPrismatic, f.mechanism,
                                   f.bodies[kSlider4], at(0, 0, 0), i, kSlider4Joint);
  slider4.lower = -1000.0;
  slider4.upper = 1000.0;
  robot.joints = {world_joint, crank, coupler, slider3, slider4};
  return robot;
}

std::vector<JointPose> fixedJointPoses(const RobotDescription& robot) {
  std::vector<JointPose> poses;
  for (const JointDescription& j : robot.joints)
    if (j.type == JointDescription::Type::kFixed) poses.push_back({&j, j.transform(0.0)});
  return poses;
}

std::vector<JointPose> movingJointPoses(const RobotDescription& robot, const JointValues& joints) {
  std::vector<JointPose> poses;
  for (const JointDescription& j : robot.joints)
    if (j.type != JointDescription::Type::kFixed)
      poses.push_back({&j, j.transform(joints.position[j.joint_index])});
  return poses;
}

}  // namespace kane_sim
