#pragma once

#include <geometry_msgs/Transform.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include "longterm_mapper2d/core/cloud/rich_point.h"
#include "longterm_mapper2d/core/map/occupancy_grid.h"

#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d_ros {

// sensor_msgs/LaserScan -> core scan. The stamp is the header stamp in seconds; ranges are copied
// unchanged (cleaning is the core's job, so the node and the offline tool clean alike).
longterm_mapper2d::LaserScan FromRosScan(const sensor_msgs::LaserScan& msg);

// The planar part of a 3D transform: x, y and the yaw of the rotation.
longterm_mapper2d::Pose2 FromRosTransform(const geometry_msgs::Transform& transform);
geometry_msgs::Transform ToRosTransform(const longterm_mapper2d::Pose2& pose);

// Core occupancy grid (row-major from the bottom row, -1 unknown, 0..100) -> nav_msgs.
nav_msgs::OccupancyGrid ToRosGrid(const longterm_mapper2d::OccupancyGrid& grid,
                                  const std::string& frame, const ros::Time& stamp);
// Cloud points (x, y, z = 0) as a PointCloud2 with float32 x, y, z.
sensor_msgs::PointCloud2 ToRosCloud(const longterm_mapper2d::Cloud& cloud, const std::string& frame,
                                    const ros::Time& stamp);

}  // namespace longterm_mapper2d_ros
