// The Mapper's trajectory: every input scan's pose, smoothed across local-map boundaries and
// refined against the finished map, and the same poses anchored to their local maps for later
// sessions.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

#include "longterm_mapper2d/core/common/parallel_for.h"
#include "longterm_mapper2d/core/mapping/mapper.h"
#include "longterm_mapper2d/core/mapping/trajectory_refiner.h"
#include "longterm_mapper2d/core/mapping/trajectory_smoothing.h"

namespace longterm_mapper2d {

std::vector<StampedPose2> Mapper::Trajectory() const {
  std::vector<StampedPose2> trajectory;
  trajectory.reserve(trajectory_.size());
  const Pose2 map_T_tracker = MapTTracker();
  for (const auto& entry : trajectory_) {
    const Pose2 pose = entry.in_map     ? entry.pose
                       : entry.attached ? nodes_.at(entry.node).map_T_node * entry.pose
                                        : map_T_tracker * entry.pose;
    trajectory.push_back({entry.stamp_s, pose});
  }
  const bool smooth = options_.trajectory.half_window_s > 0.0;
  const bool refined = std::any_of(trajectory_.begin(), trajectory_.end(), [](const auto& entry) {
    return entry.attached && entry.refined.has_value();
  });
  if (!smooth && !refined) return trajectory;
  // Smoothed across node boundaries, stretch by stretch of scans that hang off nodes (a stretch
  // recorded in localization, fixed in the map, or the one still pending, is not).
  std::vector<double> stamps;
  std::vector<bool> attached;
  std::vector<Pose2> map_T_base, tracker_T_base;
  for (std::size_t i = 0; i < trajectory_.size(); ++i) {
    stamps.push_back(trajectory_[i].stamp_s);
    attached.push_back(trajectory_[i].attached);
    map_T_base.push_back(trajectory[i].pose);
    tracker_T_base.push_back(trajectory_[i].tracker_T_base);
  }
  SmoothStretches(stamps, attached, tracker_T_base, options_.trajectory.half_window_s, map_T_base);
  // Then the refinement's corrections (RefineTrajectory), each the refined pose of a waypoint scan
  // against its smoothed pose, spread over the scans around it.
  if (refined) {
    std::vector<std::optional<Pose2>> corrections(trajectory_.size());
    for (std::size_t i = 0; i < trajectory_.size(); ++i) {
      const TrajectoryEntry& entry = trajectory_[i];
      if (!entry.attached || !entry.refined) continue;
      corrections[i] =
          (nodes_.at(entry.node).map_T_node * *entry.refined) * map_T_base[i].inverse();
    }
    CorrectStretches(stamps, attached, corrections, options_.trajectory_refinement.half_window_s,
                     map_T_base);
  }
  for (std::size_t i = 0; i < trajectory.size(); ++i) trajectory[i].pose = map_T_base[i];
  return trajectory;
}

void Mapper::RefineTrajectory() {
  const TrajectoryRefinementOptions& options = options_.trajectory_refinement;
  if (!options.enabled || refinement_scans_.empty() || nodes_.empty()) return;
  ScopedStageTimer timer(stats_.stage_times, "trajectory_refinement");
  // Aligned from where the trajectory has them now (an earlier refinement included), with every
  // local map at its current pose.
  const std::vector<StampedPose2> trajectory = Trajectory();
  const TrajectoryRefiner refiner(options, options_.registration, options_.cloud, nodes_);
  std::vector<std::optional<Pose2>> map_T_base(refinement_scans_.size());
  ParallelFor(refinement_scans_.size(), options.threads, [&](std::size_t k) {
    const RefinementScan& scan = refinement_scans_[k];
    if (!trajectory_[scan.entry].attached) return;
    map_T_base[k] = refiner.Align(scan.scan, scan.base_T_laser, trajectory[scan.entry].pose);
  });
  std::uint64_t aligned = 0;
  for (std::size_t k = 0; k < refinement_scans_.size(); ++k) {
    TrajectoryEntry& entry = trajectory_[refinement_scans_[k].entry];
    entry.refined.reset();
    if (!map_T_base[k]) continue;
    entry.refined = nodes_.at(entry.node).map_T_node.inverse() * *map_T_base[k];
    ++aligned;
  }
  stats_.counters["trajectory_refinement_scans"] = refinement_scans_.size();
  stats_.counters["trajectory_refinement_aligned"] = aligned;
}

std::vector<AnchoredPose> Mapper::TrajectoryAnchors() const {
  std::vector<AnchoredPose> anchors;
  anchors.reserve(trajectory_.size());
  const Pose2 map_T_tracker = MapTTracker();
  // Attached scans are anchored where the (smoothed) trajectory has them, in their node's frame:
  // re-expressed in this map they give Trajectory() back. Each carries its written pose too, the
  // chain along which a later re-expression smooths again.
  const std::vector<StampedPose2> trajectory = Trajectory();
  for (std::size_t i = 0; i < trajectory_.size(); ++i) {
    const TrajectoryEntry& entry = trajectory_[i];
    if (entry.in_map || (!entry.attached && !last_node_)) {
      anchors.push_back({entry.stamp_s, kMapFrame,
                         entry.in_map ? entry.pose : map_T_tracker * entry.pose,
                         trajectory[i].pose});
    } else if (entry.attached) {
      anchors.push_back({entry.stamp_s, entry.node,
                         nodes_.at(entry.node).map_T_node.inverse() * trajectory[i].pose,
                         trajectory[i].pose});
    } else {
      const Pose2& map_T_last = nodes_.at(*last_node_).map_T_node;
      anchors.push_back({entry.stamp_s, *last_node_,
                         map_T_last.inverse() * map_T_tracker * entry.pose, trajectory[i].pose});
    }
  }
  return anchors;
}

}  // namespace longterm_mapper2d
