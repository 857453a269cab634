#pragma once

#include <geometry_msgs/Transform.h>
#include <sensor_msgs/LaserScan.h>

#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d_ros {

// sensor_msgs/LaserScan -> core scan. The stamp is the header stamp in seconds; ranges are copied
// unchanged (cleaning is the core's job, so the node and the offline tool clean alike).
longterm_mapper2d::LaserScan FromRosScan(const sensor_msgs::LaserScan& msg);

// The planar part of a 3D transform: x, y and the yaw of the rotation.
longterm_mapper2d::Pose2 FromRosTransform(const geometry_msgs::Transform& transform);
geometry_msgs::Transform ToRosTransform(const longterm_mapper2d::Pose2& pose);

}  // namespace longterm_mapper2d_ros
