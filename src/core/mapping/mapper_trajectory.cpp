// The Mapper's trajectory: every input scan's pose, smoothed across local-map boundaries, and the
// same poses anchored to their local maps for later sessions.
#include <vector>

#include "longterm_mapper2d/core/mapping/mapper.h"
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
  // Smoothed across node boundaries, stretch by stretch of scans that hang off nodes (a stretch
  // recorded in localization, fixed in the map, or the one still pending, is not).
  if (options_.trajectory.half_window_s <= 0.0) return trajectory;
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
  for (std::size_t i = 0; i < trajectory.size(); ++i) trajectory[i].pose = map_T_base[i];
  return trajectory;
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
