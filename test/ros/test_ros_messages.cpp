// The message-filling path, without a master: rosparam -> config, joint_states, tf, state.
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "kane_sim/config/load_config.h"
#include "kane_sim/estimate/mechanism_estimator.h"
#include "kane_sim/ros/estimate_messages.h"
#include "kane_sim/ros/markers.h"
#include "kane_sim/ros/messages.h"
#include "kane_sim/ros/param_yaml.h"
#include "kane_sim/sim/csv_format.h"
#include "kane_sim/sim/simulator.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

XmlRpc::XmlRpcValue rosparamView() {
  // What `rosparam load config/mechanism.yaml` puts on the server, as the node reads it back.
  XmlRpc::XmlRpcValue root;
  root["mechanism"]["rod_mass"] = 1.0;
  root["mechanism"]["rod_half_length"] = 0.25;
  root["mechanism"]["slider3_mass"] = 0.5;
  root["mechanism"]["slider4_mass"] = 0.8;
  root["mechanism"]["spring_stiffness"] = 200;  // an int, as rosparam stores "200"
  root["mechanism"]["gravity"] = 9.81;
  root["initial_state"]["q1"] = 0.5235987755982988;
  root["initial_state"]["q2"] = 1.1660254037844386;
  root["initial_state"]["u1"] = 0.0;
  root["initial_state"]["u2"] = 0.0;
  root["simulation"]["publish_clock"] = true;
  root["simulation"]["integrator"] = std::string("dopri5");
  root["frames"]["prefix"] = std::string("robot_a");
  return root;
}

TEST(RosParams, RosparamViewLoadsLikeTheFile) {
  XmlRpc::XmlRpcValue params = rosparamView();
  const Config c = loadConfig(yamlFromXmlRpc(params)).config;
  const Config f = test::defaultConfig();
  EXPECT_EQ(c.mechanism.rod_mass, f.mechanism.rod_mass);
  EXPECT_EQ(c.mechanism.spring_stiffness, 200.0);
  EXPECT_EQ(c.mechanism.rod_inertia, f.mechanism.rod_inertia);
  EXPECT_EQ(c.initial_state.q2, f.initial_state.q2);
  EXPECT_TRUE(c.simulation.publish_clock);
  EXPECT_EQ(c.simulation.integrator, IntegratorType::kDopri5);
  EXPECT_EQ(c.frames.prefix, "robot_a");
}

TEST(RosParams, BadRosparamValuesNameTheKey) {
  XmlRpc::XmlRpcValue params = rosparamView();
  params["mechanism"]["rod_mass"] = std::string("heavy");
  EXPECT_THROW(
      {
        try {
          loadConfig(yamlFromXmlRpc(params));
        } catch (const ConfigError& e) {
          EXPECT_EQ(e.key(), "mechanism.rod_mass");
          throw;
        }
      },
      ConfigError);
  params = rosparamView();
  params["initial_state"]["q1"] = std::nan("");
  try {
    loadConfig(yamlFromXmlRpc(params));
    ADD_FAILURE() << "NaN accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "initial_state.q1");
    EXPECT_NE(std::string(e.what()).find("finite"), std::string::npos) << e.what();
  }
}

class MessagesTest : public ::testing::Test {
 protected:
  MessagesTest() : config_(test::defaultConfig()), sim_(config_), robot_(describeRobot(config_)) {
    sim_.setTorque(3.0);
    for (int i = 0; i < 437; ++i) sim_.step();
  }
  Config config_;
  Simulator sim_;
  RobotDescription robot_;
};

TEST_F(MessagesTest, JointStateHasFourJointsWithConsistentValues) {
  const Snapshot s = sim_.snapshot();
  const auto msg = jointStateMessage(s, ros::Time(12, 5));
  const double L = config_.mechanism.rod_half_length;
  ASSERT_EQ(msg.name, (std::vector<std::string>{"crank_joint", "coupler_joint", "slider3_joint",
                                                "slider4_joint"}));
  ASSERT_EQ(msg.position.size(), 4u);
  ASSERT_EQ(msg.velocity.size(), 4u);
  ASSERT_EQ(msg.effort.size(), 4u);
  EXPECT_EQ(msg.header.stamp, ros::Time(12, 5));
  EXPECT_DOUBLE_EQ(msg.position[0], s.state.q1);
  EXPECT_DOUBLE_EQ(msg.position[1], -2 * s.state.q1);
  EXPECT_DOUBLE_EQ(msg.position[2], 4 * L * std::cos(s.state.q1));
  EXPECT_DOUBLE_EQ(msg.position[3], s.state.q2);
  EXPECT_DOUBLE_EQ(msg.effort[0], 3.0);
  EXPECT_EQ(msg.effort[1], 0.0);

  // Velocities agree with the change of positions over one more short step (to O(dt)).
  const double dt = sim_.stepSize();
  sim_.step();
  const auto next = jointStateMessage(sim_.snapshot(), ros::Time(12, 6));
  for (int j = 0; j < 4; ++j) {
    const double mean_velocity = 0.5 * (msg.velocity[j] + next.velocity[j]);
    EXPECT_NEAR((next.position[j] - msg.position[j]) / dt, mean_velocity,
                1e-4 * (1 + std::abs(mean_velocity)))
        << msg.name[j];
  }
}

Eigen::Isometry3d toEigen(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.translate(Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z));
  iso.rotate(Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z));
  return iso;
}

TEST_F(MessagesTest, StaticTransformIsWorldToMechanism) {
  const auto t = staticTransforms(robot_, ros::Time(1));
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].header.frame_id, "world");
  EXPECT_EQ(t[0].child_frame_id, "mechanism");
  EXPECT_EQ(t[0].header.stamp, ros::Time(1));
  const Eigen::Vector3d below = toEigen(t[0].transform) * Eigen::Vector3d(1, 0, 0);
  EXPECT_TRUE(below.isApprox(Eigen::Vector3d(0, 0, 1.0), 1e-12)) << below.transpose();
}

// The moving frames form the kinematic chain: mechanism -> rod1 -> rod2, mechanism -> sliders.
TEST_F(MessagesTest, JointTransformsFormTheKinematicChain) {
  const Snapshot s = sim_.snapshot();
  const double L = config_.mechanism.rod_half_length;
  const auto t = jointTransforms(robot_, s.joints, ros::Time(3));
  ASSERT_EQ(t.size(), 4u);
  const char* parents[] = {"mechanism", "rod1", "mechanism", "mechanism"};
  const char* children[] = {"rod1", "rod2", "slider3", "slider4"};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(t[i].header.frame_id, parents[i]);
    EXPECT_EQ(t[i].child_frame_id, children[i]);
    EXPECT_EQ(t[i].header.stamp, ros::Time(3));
  }
  const Eigen::Isometry3d rod1 = toEigen(t[0].transform);
  const Eigen::Isometry3d rod2 = rod1 * toEigen(t[1].transform);
  EXPECT_LT((rod2 * Eigen::Vector3d(2 * L, 0, 0) - s.geometry.pin_b).norm(), 1e-12);
  EXPECT_LT((rod1 * Eigen::Vector3d(L, 0, 0) - s.geometry.rod1_center).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(t[2].transform.translation.x, s.geometry.pin_b.x());
  EXPECT_DOUBLE_EQ(t[3].transform.translation.x, s.state.q2);
}

TEST(FrameNames, PrefixIsJoinedWithASlashAndWorldIsShared) {
  FrameSettings s;
  s.prefix = "robot_a";
  const FrameNames a(s);
  EXPECT_EQ(a.mechanism, "robot_a/mechanism");
  EXPECT_EQ(a.bodies[kRod2], "robot_a/rod2");
  EXPECT_EQ(a.world, "world");
  s.prefix = "robot_b/";
  EXPECT_EQ(FrameNames(s).bodies[kSlider4], "robot_b/slider4");
}

TEST_F(MessagesTest, MechanismStateCarriesTheSnapshot) {
  Snapshot s = sim_.snapshot();
  s.command.commanded = 80.0;  // a command beyond the limit: the applied torque differs
  const auto msg = mechanismStateMessage(s, 0.97, ros::Time(5), "mechanism");
  EXPECT_EQ(msg.header.frame_id, "mechanism");
  EXPECT_DOUBLE_EQ(msg.sim_time, s.time);
  EXPECT_DOUBLE_EQ(msg.q[0], s.state.q1);
  EXPECT_DOUBLE_EQ(msg.u[1], s.state.u2);
  EXPECT_DOUBLE_EQ(msg.u_dot[0], s.u_dot[0]);
  EXPECT_EQ(msg.commanded_torque, 80.0);
  EXPECT_EQ(msg.applied_torque, 3.0);
  EXPECT_NEAR(msg.active_forces[0] + msg.inertia_forces[0], 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(msg.total_energy,
                   msg.kinetic_energy + msg.gravitational_energy + msg.spring_energy);
  EXPECT_DOUBLE_EQ(msg.motor_work, s.motor_work);
  EXPECT_EQ(msg.real_time_factor, 0.97);
  // What Kane's method shows: the reactions, each load's power, each body's kinetic energy.
  EXPECT_EQ(msg.pin_o_force[0], s.constraint_forces.pin_o.x());
  EXPECT_EQ(msg.pin_a_force[1], s.constraint_forces.pin_a.y());
  EXPECT_EQ(msg.pin_b_force[0], s.constraint_forces.pin_b.x());
  EXPECT_EQ(msg.rail_force_slider3, s.constraint_forces.rail_slider3);
  EXPECT_EQ(msg.spring_force, s.constraint_forces.spring);
  EXPECT_TRUE(msg.reactions_determinate);
  EXPECT_NE(msg.pin_o_force[0], 0.0);  // the ground carries the weight
  // Each load's power under its name, in the model's load order.
  ASSERT_EQ(msg.load_names.size(), static_cast<std::size_t>(kNumLoadNames));
  ASSERT_EQ(msg.load_powers.size(), static_cast<std::size_t>(kNumLoadNames));
  for (int n = 0; n < kNumLoadNames; ++n) {
    EXPECT_EQ(msg.load_names[n], kLoadInfo[n].name);
    EXPECT_EQ(msg.load_powers[n], s.load_powers.by_name[n]) << kLoadInfo[n].name;
  }
  EXPECT_EQ(msg.load_powers[static_cast<int>(LoadName::kMotor)], 3.0 * s.state.u1);
  const std::string definition = ros::message_traits::definition<kane_sim::MechanismState>();
  // A field is declared as "<type> <name>" followed by spaces (a comment) or the line's end.
  const auto declares = [&definition](const std::string& name) {
    return definition.find(" " + name + " ") != std::string::npos ||
           definition.find(" " + name + "\n") != std::string::npos;
  };
  for (const CsvColumn& c : csvColumns()) {
    if (!c.message_field.empty()) {
      EXPECT_TRUE(declares(c.message_field)) << c.message_field;
    }
  }
  // And the other way: one table names every output. Each field of the message (its top-level
  // declarations, "<type> <name>") is a column's field, but the header, the node's
  // real_time_factor and load_names (the powers' keys).
  std::set<std::string> carried = {"header", "real_time_factor", "load_names"};
  for (const CsvColumn& c : csvColumns()) carried.insert(c.message_field);
  std::istringstream lines(definition.substr(0, definition.find("\n===")));
  int fields = 0;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string type, name;
    if (line.empty() || line[0] == '#' || !(words >> type >> name) || name.find('=') == 0) continue;
    ++fields;
    EXPECT_TRUE(carried.count(name)) << "MechanismState." << name << " has no output column";
  }
  EXPECT_GT(fields, 30);  // the parse found the fields (36 today)
  double kinetic = 0.0;
  for (double t : msg.body_kinetic_energy) kinetic += t;
  EXPECT_NEAR(kinetic, msg.kinetic_energy, 1e-12);
  EXPECT_EQ(msg.impact_energy, 0.0);
}

visualization_msgs::Marker torqueArrow(const visualization_msgs::MarkerArray& array) {
  for (const auto& m : array.markers)
    if (m.ns == "torque") return m;
  throw std::runtime_error("no torque marker");
}

// The torque arrow is drawn while a torque acts and deleted (not made transparent, which rviz
// warns about) when none does; same namespace and id either way.
TEST_F(MessagesTest, TorqueArrowIsDeletedAtZeroTorque) {
  Snapshot s = sim_.snapshot();
  s.command.torque_limit = 50.0;
  s.torque = 10.0;
  const auto on = torqueArrow(mechanismMarkers(s, robot_.frames, ros::Time(1)));
  EXPECT_EQ(on.action, visualization_msgs::Marker::ADD);
  EXPECT_EQ(on.color.a, 1.0f);
  EXPECT_EQ(on.header.frame_id, robot_.frames.bodies[kRod1]);
  EXPECT_NEAR(on.points[0].x, s.geometry.rod_length, 1e-12);  // A, in rod 1's frame
  // Its length grows with the torque from a visible least (head and shaft) to 0.3 m at the limit.
  const auto length = [](const visualization_msgs::Marker& m) {
    return std::hypot(m.points[1].x - m.points[0].x, m.points[1].y - m.points[0].y);
  };
  EXPECT_NEAR(length(on), 0.08 + 0.22 * 10.0 / 50.0, 1e-12);
  s.torque = 5.0;  // a tenth of the limit: longer than the 0.06 m head
  EXPECT_GT(length(torqueArrow(mechanismMarkers(s, robot_.frames, ros::Time(1)))), 0.1);
  s.torque = -80.0;  // beyond the limit: the full length, the other way
  EXPECT_NEAR(length(torqueArrow(mechanismMarkers(s, robot_.frames, ros::Time(1)))), 0.3, 1e-12);
  s.torque = 0.0;
  const auto off = torqueArrow(mechanismMarkers(s, robot_.frames, ros::Time(2)));
  EXPECT_EQ(off.action, visualization_msgs::Marker::DELETE);
  EXPECT_EQ(off.id, on.id);
}

// Every marker is drawn in the frame of the link it belongs to, frame-locked, so that rviz
// places it with the transform it draws that link with. Carried through the tf of the snapshot,
// each lands where the geometry says: the pins on O, A, B, the spring from B to C, the arrow at A
// perpendicular to rod 1.
TEST_F(MessagesTest, MarkersSitInTheirLinksFrames) {
  sim_.setTorque(5.0);
  for (int i = 0; i < 321; ++i) ASSERT_TRUE(sim_.step().ok);
  Snapshot s = sim_.snapshot();
  s.command.torque_limit = 50.0;
  const PublishedMessages msgs = buildMessages(s, robot_, 1.0, ros::Time(3));
  // Each frame's pose in `mechanism` from the published tf (one level below it).
  std::map<std::string, Eigen::Isometry3d> pose;
  pose[robot_.frames.mechanism] = Eigen::Isometry3d::Identity();
  for (const auto& t : msgs.tf.transforms) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << t.transform.translation.x, t.transform.translation.y,
        t.transform.translation.z;
    T.linear() = Eigen::Quaterniond(t.transform.rotation.w, t.transform.rotation.x,
                                    t.transform.rotation.y, t.transform.rotation.z)
                     .toRotationMatrix();
    ASSERT_TRUE(pose.count(t.header.frame_id)) << t.header.frame_id;
    pose[t.child_frame_id] = pose[t.header.frame_id] * T;
  }
  const auto at = [&](const visualization_msgs::Marker& m, const geometry_msgs::Point& p) {
    EXPECT_TRUE(m.frame_locked) << m.ns;
    return Eigen::Vector3d(pose.at(m.header.frame_id) * Eigen::Vector3d(p.x, p.y, p.z));
  };
  const MechanismGeometry& g = s.geometry;
  for (const auto& m : msgs.markers.markers) {
    if (m.ns == "pins") {
      const Eigen::Vector3d expected[] = {g.pivot_o, g.pin_a, g.pin_b};
      EXPECT_LT((at(m, m.pose.position) - expected[m.id] - Eigen::Vector3d(0, 0, 0.02)).norm(),
                1e-12)
          << "pin " << m.id;
    } else if (m.ns == "spring") {
      EXPECT_NEAR(at(m, m.points.front()).x(), g.pin_b.x(), 1e-12);
      EXPECT_NEAR(at(m, m.points.back()).x(), g.point_c.x(), 1e-12);
    } else if (m.ns == "torque") {
      const Eigen::Vector3d base = at(m, m.points[0]), tip = at(m, m.points[1]);
      EXPECT_LT((base - g.pin_a - Eigen::Vector3d(0, 0, 0.03)).norm(), 1e-12);
      EXPECT_NEAR((tip - base).dot(g.pin_a - g.pivot_o), 0.0, 1e-12) << "perpendicular to rod 1";
      EXPECT_GT((g.pin_a - g.pivot_o).cross(tip - base).z(), 0.0) << "turning +k for M_m > 0";
    }
  }
}

TEST(SimStamp, FixedEpochPlusSimTime) {
  EXPECT_EQ(simStamp(0.0), ros::Time(1000000000, 0));
  EXPECT_EQ(simStamp(1.25), ros::Time(1000000001, 250000000));
  // Past ROS's range (ros::Duration aborted there before): clamped, never thrown.
  EXPECT_TRUE(isStampable(kMaxStampableSimTime));
  EXPECT_FALSE(isStampable(2.2e9));
  EXPECT_FALSE(isStampable(std::nan("")));
  EXPECT_EQ(simStamp(2.2e9), simStamp(kMaxStampableSimTime));
  EXPECT_EQ(simStamp(std::nan("")), simStamp(0.0));
}

// The observer's /diagnostics: a silence longer than estimator.restart_gap is a WARN naming how
// old the estimate is, whatever the last window said; before the first reading, waiting.
TEST(ObserverStatus, SilenceIsAWarning) {
  const Config config = loadConfigFile(defaultConfigFile()).config;
  MechanismEstimator estimator(config);
  const auto waiting = estimatorStatus(estimator, "/observer", 5.0);
  EXPECT_EQ(waiting.level, diagnostic_msgs::DiagnosticStatus::OK);
  EXPECT_NE(waiting.message.find("waiting for joint_states"), std::string::npos);
  RigReading r;
  r.stamp = 1.0;
  r.q1 = config.initial_state.q1;
  r.q2 = config.initial_state.q2;
  ASSERT_EQ(estimator.update(r).event, EstimatorEvent::kStarted);
  EXPECT_EQ(estimatorStatus(estimator, "/observer", 0.5 * config.estimator.restart_gap).level,
            diagnostic_msgs::DiagnosticStatus::OK);
  const auto silent = estimatorStatus(estimator, "/observer", 2.5 * config.estimator.restart_gap);
  EXPECT_EQ(silent.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(silent.message.find("no usable joint_states reading for 2.5 s"), std::string::npos)
      << silent.message;
}

}  // namespace
}  // namespace kane_sim
