// The robot description: its joint poses put every frame where the physics puts the body, and
// its URDF, read back by urdfdom's own parser (the one robot_state_publisher and rviz use),
// holds the config's masses, inertia and lengths for both shipped configs.
#include <cmath>
#include <memory>
#include <random>

#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include "kane_sim/description/joint_values.h"
#include "kane_sim/description/robot_description.h"
#include "kane_sim/description/urdf.h"
#include "kane_sim/model/mechanism_model.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

// Pose of `link` in the mechanism frame, composed along the tree from the joint values.
Eigen::Isometry3d linkPose(const RobotDescription& robot, const JointValues& joints,
                           const std::string& link) {
  if (link == robot.frames.mechanism) return Eigen::Isometry3d::Identity();
  for (const JointPose& p : movingJointPoses(robot, joints))
    if (p.joint->child == link) return linkPose(robot, joints, p.joint->parent) * p.parent_to_child;
  throw std::runtime_error("no joint moves " + link);
}

// At random states, the frames composed from joint_states' values sit exactly where the
// model's geometry puts the pins, sliders and mass centres: the tf tree and the physics agree.
TEST(RobotDescription, FramesFollowTheModelGeometryAtRandomStates) {
  const Config config = test::defaultConfig();
  const RobotDescription robot = describeRobot(config);
  const MechanismModel model = mechanismModel(config);
  const double L = config.mechanism.rod_half_length;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-10, 10), x(-2, 3), speed(-50, 50);
  for (int n = 0; n < 200; ++n) {
    const State s{angle(rng), x(rng), speed(rng), speed(rng)};
    const MechanismKinematics k = model.kinematics(s);
    const JointValues j = jointValues(k, s, 0.0);
    const MechanismGeometry& g = k.geometry;
    const auto& f = robot.frames;
    const Eigen::Isometry3d rod1 = linkPose(robot, j, f.bodies[kRod1]);
    const Eigen::Isometry3d rod2 = linkPose(robot, j, f.bodies[kRod2]);
    EXPECT_LT((rod1.translation() - g.pivot_o).norm(), 1e-12);
    EXPECT_LT((rod1 * Eigen::Vector3d(L, 0, 0) - g.rod1_center).norm(), 1e-12);
    EXPECT_LT((rod1 * Eigen::Vector3d(2 * L, 0, 0) - g.pin_a).norm(), 1e-12);
    EXPECT_LT((rod2.translation() - g.pin_a).norm(), 1e-12);
    EXPECT_LT((rod2 * Eigen::Vector3d(L, 0, 0) - g.rod2_center).norm(), 1e-12);
    EXPECT_LT((rod2 * Eigen::Vector3d(2 * L, 0, 0) - g.pin_b).norm(), 1e-12);
    EXPECT_LT((linkPose(robot, j, f.bodies[kSlider3]).translation() - g.pin_b).norm(), 1e-12);
    EXPECT_LT((linkPose(robot, j, f.bodies[kSlider4]).translation() - g.point_c).norm(), 1e-12);
    // Rod 2's x axis points from A to B.
    EXPECT_LT((rod2.linear() * Eigen::Vector3d::UnitX() - (g.pin_b - g.pin_a) / (2 * L)).norm(),
              1e-12);
  }
}

TEST(RobotDescription, WorldJointPutsGravityAlongWorldMinusZ) {
  const Config config = test::defaultConfig();
  // JointPose points into the description: keep it alive (a temporary freed it at once).
  const RobotDescription robot = describeRobot(config);
  const std::vector<JointPose> fixed = fixedJointPoses(robot);
  ASSERT_EQ(fixed.size(), 1u);
  EXPECT_EQ(fixed[0].joint->parent, "world");
  EXPECT_EQ(fixed[0].joint->child, "mechanism");
  const Eigen::Isometry3d& world_T_mech = fixed[0].parent_to_child;
  EXPECT_LT((world_T_mech.translation() - Eigen::Vector3d(0, 0, config.frames.pivot_height)).norm(),
            1e-15);
  // One metre along the textbook's x (down) is one metre lower; k = i x j maps to world x.
  EXPECT_LT((world_T_mech * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(0, 0, 1.0)).norm(), 1e-12);
  EXPECT_NEAR(world_T_mech.linear().determinant(), 1.0, 1e-12);
}

class Urdf : public ::testing::TestWithParam<const char*> {};

// urdfdom parses the URDF and finds the config in it: masses, rod inertia, lengths, joints.
TEST_P(Urdf, ParsesAndHoldsTheConfig) {
  const Config c = loadConfigFile(test::configPath(GetParam())).config;
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(toUrdf(describeRobot(c)));
  ASSERT_TRUE(model) << "urdfdom could not parse the URDF";
  EXPECT_EQ(model->getRoot()->name, "world");
  const double L = c.mechanism.rod_half_length;
  for (const char* rod : {"rod1", "rod2"}) {
    const auto link = model->getLink(rod);
    ASSERT_TRUE(link && link->inertial) << rod;
    EXPECT_EQ(link->inertial->mass, c.mechanism.rod_mass);
    EXPECT_EQ(link->inertial->izz, c.mechanism.rod_inertia);
    EXPECT_EQ(link->inertial->iyy, c.mechanism.rod_inertia);
    EXPECT_EQ(link->inertial->ixx, 0.0);
    EXPECT_DOUBLE_EQ(link->inertial->origin.position.x, L);
    ASSERT_TRUE(link->visual && link->visual->geometry);
    const auto* cylinder = dynamic_cast<const urdf::Cylinder*>(link->visual->geometry.get());
    ASSERT_NE(cylinder, nullptr);
    EXPECT_DOUBLE_EQ(cylinder->length, 2 * L);
    ASSERT_TRUE(link->collision);
  }
  EXPECT_EQ(model->getLink("slider3")->inertial->mass, c.mechanism.slider3_mass);
  EXPECT_EQ(model->getLink("slider4")->inertial->mass, c.mechanism.slider4_mass);

  const auto crank = model->getJoint("crank_joint");
  const auto coupler = model->getJoint("coupler_joint");
  const auto slider3 = model->getJoint("slider3_joint");
  const auto slider4 = model->getJoint("slider4_joint");
  ASSERT_TRUE(crank && coupler && slider3 && slider4);
  EXPECT_EQ(crank->type, urdf::Joint::CONTINUOUS);
  EXPECT_EQ(crank->parent_link_name, "mechanism");
  EXPECT_EQ(coupler->parent_link_name, "rod1");
  EXPECT_DOUBLE_EQ(coupler->parent_to_joint_origin_transform.position.x, 2 * L);
  ASSERT_TRUE(coupler->mimic);
  EXPECT_EQ(coupler->mimic->multiplier, -2.0);
  EXPECT_EQ(slider3->type, urdf::Joint::PRISMATIC);
  EXPECT_DOUBLE_EQ(slider3->limits->upper, 4 * L);
  EXPECT_EQ(slider4->axis.x, 1.0);
  const auto world_joint = model->getJoint("world_joint");
  ASSERT_TRUE(world_joint);
  EXPECT_EQ(world_joint->parent_to_joint_origin_transform.position.z, c.frames.pivot_height);
}

INSTANTIATE_TEST_SUITE_P(ShippedConfigs, Urdf,
                         ::testing::Values("mechanism.yaml", "textbook.yaml"));

// The URDF follows the config: nothing in it is written twice.
TEST(Urdf, FollowsTheConfigAndThePrefix) {
  Config c = test::defaultConfig();
  c.mechanism.rod_half_length = 0.4;
  c.mechanism.slider4_mass = 2.5;
  c.frames.prefix = "robot_a";
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(toUrdf(describeRobot(c)));
  ASSERT_TRUE(model);
  EXPECT_EQ(model->getLink("robot_a/slider4")->inertial->mass, 2.5);
  EXPECT_DOUBLE_EQ(model->getJoint("coupler_joint")->parent_to_joint_origin_transform.position.x,
                   0.8);
  EXPECT_EQ(model->getJoint("crank_joint")->child_link_name, "robot_a/rod1");
  EXPECT_EQ(model->getRoot()->name, "world");  // shared, never prefixed
}

}  // namespace
}  // namespace kane_sim
