#include "longterm_mapper2d/core/mapping/mapper.h"

#include <cmath>

namespace longterm_mapper2d {

Mapper::Mapper(const MapperOptions& options) : options_(options) {}

ScanOutcome Mapper::AddScan(const ScanInput& input) {
  ++stats_.scans_received;
  odom_trajectory_.push_back({input.scan.stamp_s, input.odom_T_base});

  if (Status geometry = input.scan.ValidateGeometry(); !geometry.ok()) {
    ++stats_.scans_skipped["invalid_geometry"];
    return ScanOutcome::kSkipped;
  }
  if (static_cast<int>(input.scan.ranges.size()) < options_.input.min_beams) {
    ++stats_.scans_skipped["too_few_beams"];
    return ScanOutcome::kSkipped;
  }

  // Odometry only: keep a waypoint whenever the robot moved far enough since the last one.
  ScopedStageTimer timer(stats_.stage_times, "waypoints");
  bool keep = !last_waypoint_odom_T_base_.has_value();
  if (!keep) {
    const Pose2 delta = last_waypoint_odom_T_base_->Between(input.odom_T_base);
    keep = delta.translation().norm() >= options_.input.waypoint_spacing_m ||
           std::abs(delta.theta()) >= options_.input.waypoint_spacing_rad;
  }
  if (!keep) {
    ++stats_.scans_skipped["no_motion"];
    return ScanOutcome::kSkipped;
  }
  last_waypoint_odom_T_base_ = input.odom_T_base;
  waypoints_.push_back({input.odom_T_base * input.base_T_laser, input.scan});
  ++stats_.scans_processed;
  return ScanOutcome::kProcessed;
}

void Mapper::Finish() {}

std::vector<StampedPose2> Mapper::Trajectory() const {
  std::vector<StampedPose2> trajectory;
  trajectory.reserve(odom_trajectory_.size());
  for (const auto& entry : odom_trajectory_) {
    trajectory.push_back({entry.stamp_s, map_T_odom_ * entry.pose});
  }
  return trajectory;
}

std::vector<PosedScan> Mapper::WaypointScans() const {
  std::vector<PosedScan> scans = waypoints_;
  for (auto& scan : scans) scan.map_T_laser = map_T_odom_ * scan.map_T_laser;
  return scans;
}

}  // namespace longterm_mapper2d
