#pragma once

#include <optional>
#include <vector>

#include "longterm_mapper2d/core/config/mapper_options.h"
#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/mapping/mapper_stats.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d {

// What happened to one input scan.
enum class ScanOutcome { kProcessed, kSkipped };

// The façade of the core: everything the ROS node and the offline tools call. Feed it scans with
// their odometry in time order; ask it for poses, the map and statistics.
class Mapper {
 public:
  explicit Mapper(const MapperOptions& options);

  const MapperOptions& options() const { return options_; }

  // Adds one scan. Every scan, processed or skipped, gets a pose in the trajectory.
  ScanOutcome AddScan(const ScanInput& input);

  // Ends the session: final loop-closure check and optimisation.
  void Finish();

  // map_T_base for every input scan, in input order, at the final estimate.
  std::vector<StampedPose2> Trajectory() const;
  // The latest estimate of map_T_odom (what the node publishes on TF).
  Pose2 map_T_odom() const { return map_T_odom_; }
  // The raw scans kept as waypoints, placed in the map at the current estimate.
  std::vector<PosedScan> WaypointScans() const;

  const MapperStats& stats() const { return stats_; }

 private:
  MapperOptions options_;
  MapperStats stats_;
  Pose2 map_T_odom_;
  std::vector<StampedPose2> odom_trajectory_;  // odom_T_base per input scan
  std::vector<PosedScan> waypoints_;            // odom_T_laser with the raw scan
  std::optional<Pose2> last_waypoint_odom_T_base_;
};

}  // namespace longterm_mapper2d
