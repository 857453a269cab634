#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "longterm_mapper2d/core/cloud/rich_point.h"
#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d {

using NodeId = std::int64_t;

// A pose of the robot along a local map's stretch of trajectory, with the raw scan taken there.
// Waypoints render the occupancy grid and give the viewpoints of virtual scans when local maps
// merge. `session_id` is the session that took the scan (a merged node holds several sessions'),
// so that newer views can replace older ones of the same place across sessions.
struct Waypoint {
  Pose2 node_T_base;
  Pose2 base_T_laser;
  LaserScan scan;
  int session_id = 0;
};

// A graph node: a local map (cloud and waypoints, both in the node frame). The node pose is the
// robot pose at the end of the stretch its cloud covers.
struct LocalMapNode {
  NodeId id = 0;
  int session_id = 0;
  double stamp_s = 0.0;
  Pose2 map_T_node;
  Cloud cloud;
  std::vector<Waypoint> waypoints;
};

// The relative pose between consecutive nodes from the tracker, with its information (the inverse
// of the covariance accumulated over the registrations of the stretch).
struct OdometryEdge {
  NodeId from = 0;
  NodeId to = 0;
  Pose2 from_T_to;
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  // For the loop closer's candidate gate, when it differs (TrackerOptions::tight_odometry_edges).
  std::optional<Eigen::Matrix3d> gating_information;
  bool after_tracker_failure = false;
};

}  // namespace longterm_mapper2d
