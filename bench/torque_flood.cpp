// torque_flood: publishes std_msgs/Float64 on torque_command as fast as asked, for a load
// test of kane_sim_node (bench/flood.py starts three of these).
//   torque_flood RATE_HZ SECONDS [VALUE]
#include <chrono>
#include <cstdlib>
#include <thread>

#include <ros/ros.h>
#include <std_msgs/Float64.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "torque_flood", ros::init_options::AnonymousName);
  if (argc < 3) {
    ROS_FATAL("usage: torque_flood RATE_HZ SECONDS [VALUE]");
    return 2;
  }
  const double rate = std::atof(argv[1]);
  const double seconds = std::atof(argv[2]);
  std_msgs::Float64 msg;
  msg.data = argc > 3 ? std::atof(argv[3]) : 1.0;
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<std_msgs::Float64>("torque_command", 100);
  const auto period = std::chrono::duration<double>(1.0 / rate);
  auto next = std::chrono::steady_clock::now();
  const auto end = next + std::chrono::duration<double>(seconds);
  long sent = 0;
  while (ros::ok() && std::chrono::steady_clock::now() < end) {
    pub.publish(msg);
    ++sent;
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    std::this_thread::sleep_until(next);
  }
  ROS_INFO("torque_flood: sent %ld messages in %g s (%.0f Hz)", sent, seconds, sent / seconds);
  return 0;
}
