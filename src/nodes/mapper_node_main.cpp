#include <ros/ros.h>

#include "longterm_mapper2d/ros/mapper_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "mapper_node");
  ros::NodeHandle nh, private_nh("~");
  longterm_mapper2d_ros::MapperNode node(nh, private_nh);
  if (const auto status = node.Start(); !status.ok()) {
    ROS_FATAL("longterm_mapper2d: refusing to start:\n%s", status.message().c_str());
    return 1;
  }
  // Timers and services on their own threads, so that a long save never delays map -> odom.
  ros::AsyncSpinner spinner(3);
  spinner.start();
  ros::waitForShutdown();
  return 0;
}
