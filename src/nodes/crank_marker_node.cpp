#include "crank_marker_node.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <visualization_msgs/InteractiveMarker.h>

#include "kane_sim/config/frame_names.h"
#include "kane_sim/description/body_shapes.h"
#include "kane_sim/model/joint_names.h"
#include "kane_sim/ros/node_params.h"
#include "kane_sim/teleop/crank_angle.h"

namespace kane_sim {
namespace {

std::string mechanismFrame(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) {
  FrameSettings frames;
  if (!pnh.getParam("frame_prefix", frames.prefix)) {
    const std::string sim_node = pnh.param<std::string>("sim_node", "kane_sim");
    nh.getParam(sim_node + "/frames/prefix", frames.prefix);
  }
  return FrameNames(frames).mechanism;
}

geometry_msgs::Quaternion aboutZ(double angle) {
  geometry_msgs::Quaternion q;
  q.w = std::cos(angle / 2);
  q.z = std::sin(angle / 2);
  return q;
}

std_msgs::ColorRGBA setpointColor(float alpha) {
  std_msgs::ColorRGBA color;
  color.r = MarkerColors::kSetpoint[0];
  color.g = MarkerColors::kSetpoint[1];
  color.b = MarkerColors::kSetpoint[2];
  color.a = alpha;
  return color;
}

// A flat ring in the crank's plane (the mechanism frame's xy), in the setpoint colour: rviz
// would draw a rotate control's default ring blue, the rods' colour.
visualization_msgs::Marker ring(double scale) {
  visualization_msgs::Marker ring;
  ring.type = visualization_msgs::Marker::TRIANGLE_LIST;
  ring.pose.orientation.w = 1.0;
  ring.scale.x = ring.scale.y = ring.scale.z = 1.0;
  ring.color = setpointColor(0.5f);
  const double inner = 0.42 * scale, outer = 0.5 * scale;
  constexpr int kSegments = 72;
  const auto point = [](double radius, double angle) {
    geometry_msgs::Point p;
    p.x = radius * std::cos(angle);
    p.y = radius * std::sin(angle);
    return p;
  };
  for (int i = 0; i < kSegments; ++i) {
    const double a0 = 2 * M_PI * i / kSegments, a1 = 2 * M_PI * (i + 1) / kSegments;
    for (const auto& [radius, angle] :
         {std::pair{inner, a0}, {outer, a0}, {outer, a1}, {inner, a0}, {outer, a1}, {inner, a1}})
      ring.points.push_back(point(radius, angle));
  }
  return ring;
}

// A ring about z to drag (the control's x axis, turned onto z) and an arrow along x showing
// the setpoint's direction: where the controller will hold rod 1.
visualization_msgs::InteractiveMarker crankMarker(const std::string& frame, double scale) {
  visualization_msgs::InteractiveMarker marker;
  marker.header.frame_id = frame;
  marker.name = CrankMarkerNode::kMarkerName;
  marker.description = "crank setpoint (drag the ring)";
  marker.scale = static_cast<float>(scale);
  marker.pose.orientation.w = 1.0;

  visualization_msgs::InteractiveMarkerControl rotate;
  rotate.name = "rotate_crank";
  rotate.interaction_mode = visualization_msgs::InteractiveMarkerControl::ROTATE_AXIS;
  rotate.orientation_mode = visualization_msgs::InteractiveMarkerControl::FIXED;
  rotate.orientation.w = M_SQRT1_2;  // x onto z: a quarter turn about y
  rotate.orientation.y = M_SQRT1_2;
  rotate.markers.push_back(ring(scale));
  marker.controls.push_back(rotate);

  visualization_msgs::InteractiveMarkerControl pointer;
  pointer.name = "setpoint_arrow";
  pointer.interaction_mode = visualization_msgs::InteractiveMarkerControl::NONE;
  pointer.always_visible = true;
  visualization_msgs::Marker arrow;
  arrow.type = visualization_msgs::Marker::ARROW;
  arrow.pose.orientation.w = 1.0;
  arrow.scale.x = 0.45 * scale;  // length along x
  arrow.scale.y = arrow.scale.z = 0.04 * scale;
  arrow.color = setpointColor(1.0f);
  pointer.markers.push_back(arrow);
  marker.controls.push_back(pointer);
  return marker;
}

}  // namespace

CrankMarkerNode::CrankMarkerNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh)
    : nh_(nh), frame_(mechanismFrame(nh, private_nh)), server_("crank_marker") {
  const double scale = boundedParam(private_nh, "scale", 0.6, ParamBound::kPositive);  // [m]
  setpoint_pub_ = nh_.advertise<std_msgs::Float64>("setpoint", 10, /*latch=*/true);
  setpoint_sub_ = nh_.subscribe("setpoint", 10, &CrankMarkerNode::onSetpoint, this);
  server_.insert(crankMarker(frame_, scale),
                 [this](const visualization_msgs::InteractiveMarkerFeedbackConstPtr& feedback) {
                   onFeedback(feedback);
                 });
  server_.applyChanges();
  // Start at the controller's setpoint when it has one; else grab the crank where it is.
  const std::string controller = private_nh.param<std::string>("controller_node", "pd_controller");
  double controller_setpoint = 0.0;
  if (nh_.getParam(controller + "/setpoint", controller_setpoint) &&
      std::isfinite(controller_setpoint)) {
    setpoint_ = controller_setpoint;
    placed_ = true;
    moveMarker();
  } else {
    joint_state_sub_ = nh_.subscribe("joint_states", 1, &CrankMarkerNode::onJointState, this);
  }
  ROS_INFO(
      "crank_marker: drag the ring in rviz (InteractiveMarkers, update topic %s) to set "
      "the crank setpoint; frame %s",
      ros::names::resolve("crank_marker/update").c_str(), frame_.c_str());
}

void CrankMarkerNode::moveMarker() {
  geometry_msgs::Pose pose;
  pose.orientation = aboutZ(setpoint_);
  server_.setPose(kMarkerName, pose);
  server_.applyChanges();
}

void CrankMarkerNode::onJointState(const sensor_msgs::JointState::ConstPtr& msg) {
  if (placed_) return;
  const auto it = std::find(msg->name.begin(), msg->name.end(), kJointNames[kCrankJoint]);
  const size_t i = static_cast<size_t>(it - msg->name.begin());
  if (it == msg->name.end() || i >= msg->position.size() || !std::isfinite(msg->position[i]))
    return;
  // Grab the crank where it is: the controller holds it there until the ring is dragged.
  publishSetpoint(msg->position[i]);
  moveMarker();
  joint_state_sub_.shutdown();  // only the start position is needed
}

void CrankMarkerNode::publishSetpoint(double setpoint) {
  setpoint_ = setpoint;
  placed_ = true;
  std_msgs::Float64 msg;
  msg.data = setpoint_;
  setpoint_pub_.publish(msg);
}

void CrankMarkerNode::onFeedback(
    const visualization_msgs::InteractiveMarkerFeedbackConstPtr& feedback) {
  if (feedback->event_type != visualization_msgs::InteractiveMarkerFeedback::POSE_UPDATE) return;
  const geometry_msgs::Quaternion& q = feedback->pose.orientation;
  const std::optional<double> angle = twistAboutZ(q.w, q.x, q.y, q.z);
  if (feedback->header.frame_id != frame_ || !angle) {
    ROS_WARN_THROTTLE(5.0,
                      "crank_marker: ignored feedback in frame '%s' with orientation (%g %g %g "
                      "%g): expected a turn about z in frame '%s'",
                      feedback->header.frame_id.c_str(), q.w, q.x, q.y, q.z, frame_.c_str());
    return;
  }
  // Dragging through +-pi keeps counting turns, as the continuous crank joint does.
  publishSetpoint(unwrapNear(*angle, setpoint_));
}

void CrankMarkerNode::onSetpoint(const ros::MessageEvent<const std_msgs::Float64>& event) {
  if (event.getPublisherName() == ros::this_node::getName()) return;  // our own
  const double value = event.getMessage()->data;
  if (!std::isfinite(value)) return;  // pd_controller refuses it too
  setpoint_ = value;
  placed_ = true;
  moveMarker();
}

}  // namespace kane_sim
