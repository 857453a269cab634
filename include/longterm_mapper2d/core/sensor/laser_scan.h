#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/geometry/pose2.h"

namespace longterm_mapper2d {

// A planar range scan, as the laser delivered it (the core's mirror of sensor_msgs/LaserScan).
// Beam i points at angle_min_rad + i * angle_increment_rad in the laser frame.
struct LaserScan {
  double stamp_s = 0.0;
  std::string frame_id;
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  std::vector<float> ranges;

  double BeamAngle(std::size_t i) const { return angle_min_rad + angle_increment_rad * i; }
  double FieldOfView() const { return angle_increment_rad * ranges.size(); }
  // A range that is a real return: finite, inside [range_min_m, range_max_m).
  bool IsValidRange(float range_m) const;
  // Checks the scan geometry (not the individual ranges): beams present, a positive increment,
  // a field of view of at most 2*pi, a sane range interval.
  Status ValidateGeometry() const;
  // A laser that turns clockwise reports a negative angle_increment (legal in ROS): the same
  // beams in counter-clockwise order, with angle_min at the other end.
  void MakeCounterClockwise();
};

// One scan with what the mapper needs to place it: the odometry pose of the robot base at the
// scan stamp, and where the laser sits on the base.
struct ScanInput {
  LaserScan scan;
  Pose2 odom_T_base;
  Pose2 base_T_laser;
};

// A raw scan placed in a frame: the laser pose at the scan stamp and the scan. Used to render
// occupancy grids by ray casting and to build virtual scans.
struct PosedScan {
  Pose2 map_T_laser;
  LaserScan scan;
};

}  // namespace longterm_mapper2d
