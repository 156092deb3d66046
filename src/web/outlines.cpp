#include "kane_sim/web/outlines.h"

#include <algorithm>
#include <map>

#include <Eigen/Geometry>

namespace kane_sim {
namespace web {
namespace {

// Every link's pose in the mechanism frame: the tree walked from the mechanism frame, each joint
// composing parent -> child (fixed joints at their origin, moving ones at their value).
std::map<std::string, Eigen::Isometry3d> linkPoses(const RobotDescription& robot,
                                                   const JointValues& joints) {
  std::map<std::string, Eigen::Isometry3d> pose{
      {robot.frames.mechanism, Eigen::Isometry3d::Identity()}};
  std::vector<JointPose> all = fixedJointPoses(robot);
  const std::vector<JointPose> moving = movingJointPoses(robot, joints);
  all.insert(all.end(), moving.begin(), moving.end());
  // A joint can be listed before its parent's: repeat until nothing more is placed.
  for (bool placed = true; placed;) {
    placed = false;
    for (const JointPose& j : all) {
      const auto parent = pose.find(j.joint->parent);
      if (parent == pose.end() || pose.count(j.joint->child)) continue;
      pose[j.joint->child] = parent->second * j.parent_to_child;
      placed = true;
    }
  }
  return pose;
}

// Andrew's monotone chain: the convex hull, counter-clockwise.
std::vector<Eigen::Vector2d> convexHull(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  const auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  return hull;
}

// The shape's bounding box in its own frame: a box's size; a cylinder's 2r x 2r x length (its
// axis along z). Seen from the side a cylinder is that box's outline.
Eigen::Vector3d halfExtent(const LinkShape& shape) {
  if (shape.kind == LinkShape::Kind::kBox) return shape.box_size / 2;
  return Eigen::Vector3d(shape.radius, shape.radius, shape.length / 2);
}

}  // namespace

std::vector<LinkOutline> linkOutlines(const RobotDescription& robot, const JointValues& joints) {
  const std::map<std::string, Eigen::Isometry3d> pose = linkPoses(robot, joints);
  std::vector<LinkOutline> outlines;
  for (const LinkDescription& link : robot.links) {
    const auto at = pose.find(link.name);
    if (!link.shape || at == pose.end()) continue;
    const Eigen::Isometry3d shape_pose = at->second * link.shape->origin.transform();
    const Eigen::Vector3d h = halfExtent(*link.shape);
    std::vector<Eigen::Vector2d> corners;
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d c((i & 1 ? 1 : -1) * h.x(), (i & 2 ? 1 : -1) * h.y(),
                              (i & 4 ? 1 : -1) * h.z());
      corners.push_back((shape_pose * c).head<2>());
    }
    LinkOutline outline;
    outline.link = link.name;
    outline.polygon = convexHull(corners);
    for (const MaterialColor& m : robot.materials)
      if (m.name == link.shape->material) {
        outline.r = m.r;
        outline.g = m.g;
        outline.b = m.b;
      }
    outlines.push_back(std::move(outline));
  }
  return outlines;
}

std::vector<std::pair<std::string, Eigen::Vector2d>> linkOrigins(const RobotDescription& robot,
                                                                 const JointValues& joints) {
  const std::map<std::string, Eigen::Isometry3d> pose = linkPoses(robot, joints);
  std::vector<std::pair<std::string, Eigen::Vector2d>> origins;
  for (const LinkDescription& link : robot.links) {
    const auto at = pose.find(link.name);
    if (at != pose.end() && link.name != robot.frames.mechanism)
      origins.emplace_back(link.name, at->second.translation().head<2>());
  }
  return origins;
}

}  // namespace web
}  // namespace kane_sim
