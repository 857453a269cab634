#include "longterm_mapper2d/ros/conversions.h"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <cmath>

namespace longterm_mapper2d_ros {

longterm_mapper2d::LaserScan FromRosScan(const sensor_msgs::LaserScan& msg) {
  longterm_mapper2d::LaserScan scan;
  scan.stamp_s = msg.header.stamp.toSec();
  scan.frame_id = msg.header.frame_id;
  scan.angle_min_rad = msg.angle_min;
  scan.angle_increment_rad = msg.angle_increment;
  scan.range_min_m = msg.range_min;
  scan.range_max_m = msg.range_max;
  scan.ranges = msg.ranges;
  return scan;
}

longterm_mapper2d::Pose2 FromRosTransform(const geometry_msgs::Transform& transform) {
  const auto& q = transform.rotation;
  // Yaw of a quaternion (ZYX convention); roll and pitch are ignored in the plane.
  const double yaw = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
  return longterm_mapper2d::Pose2(transform.translation.x, transform.translation.y, yaw);
}

geometry_msgs::Transform ToRosTransform(const longterm_mapper2d::Pose2& pose) {
  geometry_msgs::Transform transform;
  transform.translation.x = pose.x();
  transform.translation.y = pose.y();
  transform.translation.z = 0.0;
  transform.rotation.x = 0.0;
  transform.rotation.y = 0.0;
  transform.rotation.z = std::sin(pose.theta() / 2.0);
  transform.rotation.w = std::cos(pose.theta() / 2.0);
  return transform;
}

nav_msgs::OccupancyGrid ToRosGrid(const longterm_mapper2d::OccupancyGrid& grid,
                                  const std::string& frame, const ros::Time& stamp) {
  nav_msgs::OccupancyGrid msg;
  msg.header.frame_id = frame;
  msg.header.stamp = stamp;
  msg.info.map_load_time = stamp;
  msg.info.resolution = static_cast<float>(grid.resolution_m);
  msg.info.width = static_cast<uint32_t>(grid.width);
  msg.info.height = static_cast<uint32_t>(grid.height);
  msg.info.origin.position.x = grid.origin_m.x();
  msg.info.origin.position.y = grid.origin_m.y();
  msg.info.origin.orientation.w = 1.0;
  msg.data.assign(grid.cells.begin(), grid.cells.end());
  return msg;
}

sensor_msgs::PointCloud2 ToRosCloud(const longterm_mapper2d::Cloud& cloud, const std::string& frame,
                                    const ros::Time& stamp) {
  sensor_msgs::PointCloud2 msg;
  msg.header.frame_id = frame;
  msg.header.stamp = stamp;
  sensor_msgs::PointCloud2Modifier modifier(msg);
  modifier.setPointCloud2FieldsByString(1, "xyz");
  modifier.resize(cloud.size());
  // The iterators take the address of the first byte: an empty cloud has none (UBSan).
  if (cloud.empty()) return msg;
  sensor_msgs::PointCloud2Iterator<float> x(msg, "x"), y(msg, "y"), z(msg, "z");
  for (const auto& p : cloud) {
    *x = static_cast<float>(p.point_m.x());
    *y = static_cast<float>(p.point_m.y());
    *z = 0.0f;
    ++x;
    ++y;
    ++z;
  }
  return msg;
}

}  // namespace longterm_mapper2d_ros
