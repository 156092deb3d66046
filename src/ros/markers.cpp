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
// [m] at the least torque: the head (0.06 m) and some shaft, so that 5 N m of 50 still shows
// (a length proportional to the torque alone drew a 3 mm stub there).
constexpr double kMinArrowLength = 0.08;

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
  // Each marker lives in the frame of the link it belongs to and is frame_locked: rviz places it
  // with the same transform it draws that link with (the latest), so at any replay rate the pins
  // sit on their joints and the arrow on rod 1. (Drawn in `mechanism` with positions from the
  // message, they came 0.4 m away from the RobotModel in a fast replay: the message and the tf
  // rviz drew the links with were of different instants.)
  const MechanismGeometry& g = snapshot.geometry;
  const std::string& rod1 = frames.bodies[kRod1];
  const std::string& slider3 = frames.bodies[kSlider3];
  const double torque_limit = snapshot.command.torque_limit;
  visualization_msgs::MarkerArray array;
  auto& out = array.markers;
  const auto locked = [&](const std::string& frame, const std::string& ns, int id, int type,
                          const float rgb[3]) {
    auto m = baseMarker(frame, stamp, ns, id, type, rgb);
    m.frame_locked = true;
    return m;
  };

  // O fixed in `mechanism`; A at the far end of rod 1 (its frame: origin O, x along the rod);
  // B at slider 3's origin. In front of the rods (+z).
  const std::pair<const std::string*, Eigen::Vector3d> pins[] = {
      {&frames.mechanism, Eigen::Vector3d::Zero()},
      {&rod1, Eigen::Vector3d(g.rod_length, 0, 0)},
      {&slider3, Eigen::Vector3d::Zero()}};
  for (int i = 0; i < 3; ++i) {
    auto m =
        locked(*pins[i].first, "pins", i, visualization_msgs::Marker::SPHERE, MarkerColors::kPin);
    m.pose.position = point(pins[i].second + Eigen::Vector3d(0, 0, 0.02));
    m.scale.x = m.scale.y = m.scale.z = shapes::kPinDiameter;
    out.push_back(m);
  }

  // The rail: the textbook's x axis from just above O to below the lowest reach of slider 4.
  auto rail = locked(frames.mechanism, "rail", 0, visualization_msgs::Marker::LINE_STRIP,
                     MarkerColors::kRail);
  rail.scale.x = 0.01;
  rail.points = {point(Eigen::Vector3d(-0.1, 0, -0.04)),
                 point(Eigen::Vector3d(std::max(2 * g.rod_length, g.point_c.x()) + 0.4, 0, -0.04))};
  out.push_back(rail);

  // The spring: a zigzag from B (slider 3's origin, whose axes are the mechanism's) to C, its
  // pitch following the elongation.
  auto spring =
      locked(slider3, "spring", 0, visualization_msgs::Marker::LINE_STRIP, MarkerColors::kSpring);
  spring.scale.x = 0.008;
  const double length = g.sliderSeparation();  // x_C - x_B
  spring.points.push_back(point(Eigen::Vector3d(0, 0, 0.01)));
  for (int i = 1; i < kSpringZigs; ++i)
    spring.points.push_back(point(
        Eigen::Vector3d(length * i / kSpringZigs, (i % 2 ? 1 : -1) * kSpringHalfWidth, 0.01)));
  spring.points.push_back(point(Eigen::Vector3d(length, 0, 0.01)));
  out.push_back(spring);

  // The driver moment: an arrow at A along the direction it turns rod 1 (rod 1's y axis in its
  // own frame), length proportional to |M_m|.
  auto arrow = locked(rod1, "torque", 0, visualization_msgs::Marker::ARROW, MarkerColors::kTorque);
  const double fraction = torque_limit > 0 ? std::min(1.0, std::abs(snapshot.torque) / torque_limit)
                                           : (snapshot.torque != 0.0 ? 1.0 : 0.0);
  const double sense = snapshot.torque >= 0 ? 1.0 : -1.0;
  const double arrow_length = kMinArrowLength + (kArrowLength - kMinArrowLength) * fraction;
  const Eigen::Vector3d at_a(g.rod_length, 0, 0.03);
  arrow.points = {point(at_a), point(at_a + Eigen::Vector3d(0, sense * arrow_length, 0))};
  arrow.scale.x = 0.015;                         // shaft diameter
  arrow.scale.y = 0.035;                         // head diameter
  arrow.scale.z = std::min(0.06, arrow_length);  // head length
  // No torque, no arrow: DELETE (a transparent ADD makes rviz warn on every message).
  if (fraction == 0.0) arrow.action = visualization_msgs::Marker::DELETE;
  out.push_back(arrow);
  return array;
}

}  // namespace kane_sim
