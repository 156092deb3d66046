#include "kane_sim/ros/markers.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "kane_sim/description/body_shapes.h"

namespace kane_sim {
namespace {

constexpr double kSpringHalfWidth = 0.03;  // [m] lateral amplitude of the zigzag
constexpr int kSpringZigs = 12;
constexpr double kArrowLength = 0.3;  // [m] at the torque limit

visualization_msgs::Marker baseMarker(const std::string& frame, const ros::Time& stamp,
                                      const std::string& ns, int id, int type, const float rgb[3]) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.color.r = rgb[0];
  m.color.g = rgb[1];
  m.color.b = rgb[2];
  m.color.a = 1.0f;
  return m;
}

geometry_msgs::Point point(const Eigen::Vector3d& p) {
  geometry_msgs::Point out;
  out.x = p.x();
  out.y = p.y();
  out.z = p.z();
  return out;
}

}  // namespace

visualization_msgs::MarkerArray mechanismMarkers(const Snapshot& snapshot, const FrameNames& frames,
                                                 const ros::Time& stamp) {
  const std::string& f = frames.mechanism;
  const MechanismGeometry& g = snapshot.geometry;
  const double torque_limit = snapshot.command.torque_limit;
  visualization_msgs::MarkerArray array;
  auto& out = array.markers;

  const Eigen::Vector3d pins[] = {g.pivot_o, g.pin_a, g.pin_b};
  for (int i = 0; i < 3; ++i) {
    auto m =
        baseMarker(f, stamp, "pins", i, visualization_msgs::Marker::SPHERE, MarkerColors::kPin);
    m.pose.position = point(pins[i] + Eigen::Vector3d(0, 0, 0.02));  // in front of the rods
    m.scale.x = m.scale.y = m.scale.z = shapes::kPinDiameter;
    out.push_back(m);
  }

  // The rail: the textbook's x axis from just above O to below the lowest reach of slider 4.
  auto rail =
      baseMarker(f, stamp, "rail", 0, visualization_msgs::Marker::LINE_STRIP, MarkerColors::kRail);
  rail.scale.x = 0.01;
  rail.points = {point(Eigen::Vector3d(-0.1, 0, -0.04)),
                 point(Eigen::Vector3d(std::max(2 * g.rod_length, g.point_c.x()) + 0.4, 0, -0.04))};
  out.push_back(rail);

  // The spring: a zigzag from B to C whose pitch follows the elongation.
  auto spring = baseMarker(f, stamp, "spring", 0, visualization_msgs::Marker::LINE_STRIP,
                           MarkerColors::kSpring);
  spring.scale.x = 0.008;
  const double x_b = g.pin_b.x(), x_c = g.point_c.x();
  spring.points.push_back(point(Eigen::Vector3d(x_b, 0, 0.01)));
  for (int i = 1; i < kSpringZigs; ++i) {
    const double x = x_b + (x_c - x_b) * i / kSpringZigs;
    spring.points.push_back(point(Eigen::Vector3d(x, (i % 2 ? 1 : -1) * kSpringHalfWidth, 0.01)));
  }
  spring.points.push_back(point(Eigen::Vector3d(x_c, 0, 0.01)));
  out.push_back(spring);

  // The driver moment: an arrow at A along the direction it turns rod 1, length ∝ |M_m|.
  auto arrow =
      baseMarker(f, stamp, "torque", 0, visualization_msgs::Marker::ARROW, MarkerColors::kTorque);
  const double fraction = torque_limit > 0 ? std::min(1.0, std::abs(snapshot.torque) / torque_limit)
                                           : (snapshot.torque != 0.0 ? 1.0 : 0.0);
  const double sense = snapshot.torque >= 0 ? 1.0 : -1.0;
  const Eigen::Vector3d tangent(-std::sin(g.rod1_angle), std::cos(g.rod1_angle), 0);
  const double length = std::max(1e-3, kArrowLength * fraction);
  arrow.points = {point(g.pin_a + Eigen::Vector3d(0, 0, 0.03)),
                  point(g.pin_a + sense * length * tangent + Eigen::Vector3d(0, 0, 0.03))};
  arrow.scale.x = 0.015;                   // shaft diameter
  arrow.scale.y = 0.035;                   // head diameter
  arrow.scale.z = std::min(0.06, length);  // head length
  // No torque, no arrow: DELETE (a transparent ADD makes rviz warn on every message).
  if (fraction == 0.0) arrow.action = visualization_msgs::Marker::DELETE;
  out.push_back(arrow);
  return array;
}

}  // namespace kane_sim
