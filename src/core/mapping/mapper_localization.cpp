// Localization mode of the Mapper: the map is frozen; the tracker's local map is aligned to the
// nearest map nodes now and then, and map -> tracker follows the alignments.
#include <algorithm>
#include <cmath>

#include "longterm_mapper2d/core/mapping/mapper.h"

namespace longterm_mapper2d {

const char* MapperModeName(MapperMode mode) {
  return mode == MapperMode::kLocalization ? "localization" : "mapping";
}

Status Mapper::SetMode(MapperMode mode) {
  if (mode == mode_) return Status::Ok();
  if (mode == MapperMode::kLocalization) {
    if (nodes_.empty() && pending_waypoints_.empty()) {
      return Status::Error("localization needs a map: load one or map for a while first");
    }
    // The open stretch becomes a node, so nothing mapped so far is lost.
    if (has_last_processed_ && !pending_waypoints_.empty()) {
      CreateNode(trajectory_.back().stamp_s, last_tracker_T_base_, stretch_after_failure_);
    }
    if (nodes_.empty()) return Status::Error("localization needs a map");
    localization_map_T_tracker_ = MapTTracker();
    last_localization_tracker_T_base_ = last_tracker_T_base_;
    first_pending_entry_ = trajectory_.size();
    mode_ = MapperMode::kLocalization;
    return Status::Ok();
  }
  // Back to mapping: the tracker frame sits where localization put it; the next processed scan
  // starts a node tied to the map node nearest to the robot (as a loaded session's first node).
  const Pose2 map_T_tracker = MapTTracker();
  mode_ = MapperMode::kMapping;
  map_T_tracker_start_ = map_T_tracker;
  if (has_last_processed_) {
    initial_map_T_base_.reset();
    last_node_.reset();
    tracker_T_stretch_start_.reset();
    const Pose2 map_T_base = map_T_tracker * last_tracker_T_base_;
    if (!nodes_.empty()) session_anchor_ = NearestNode(map_T_base);
  }
  pending_waypoints_.clear();
  last_waypoint_tracker_T_base_.reset();
  stretch_covariance_.setZero();
  stretch_gating_covariance_.setZero();
  stretch_after_failure_ = false;
  first_pending_entry_ = trajectory_.size();
  return Status::Ok();
}

void Mapper::MaybeLocalize(const Pose2& tracker_T_base) {
  const LocalizationOptions& options = options_.localization;
  const Pose2 moved = last_localization_tracker_T_base_.Between(tracker_T_base);
  if (moved.translation().norm() < options.every_m && std::abs(moved.theta()) < options.every_rad) {
    return;
  }
  last_localization_tracker_T_base_ = tracker_T_base;
  ScopedStageTimer timer(stats_.stage_times, "localization");
  const Pose2 map_T_base = MapTTracker() * tracker_T_base;
  std::vector<std::pair<double, NodeId>> nearest;
  for (const auto& [id, node] : nodes_) {
    const double d = (node.map_T_node.translation() - map_T_base.translation()).norm();
    if (d <= options.search_radius_m) nearest.emplace_back(d, id);
  }
  std::sort(nearest.begin(), nearest.end());
  if (nearest.size() > static_cast<std::size_t>(options.max_nodes))
    nearest.resize(options.max_nodes);
  // The tracker's local map seen from the robot.
  const Cloud current = Transform(tracker_T_base.inverse(), tracker_.local_map());
  for (const auto& [distance, id] : nearest) {
    const LocalMapNode& node = nodes_.at(id);
    const auto node_T_base =
        loop_closer_.AlignLocalMaps(node.cloud, current, {node.map_T_node.Between(map_T_base)});
    if (!node_T_base) continue;
    const Pose2 corrected = node.map_T_node * *node_T_base;
    if ((corrected.translation() - map_T_base.translation()).norm() > options.max_correction_m) {
      ++stats_.counters["localization_jumps_refused"];
      continue;
    }
    localization_map_T_tracker_ = corrected * tracker_T_base.inverse();
    ++stats_.counters["localization_corrections"];
    return;
  }
  ++stats_.counters["localization_failures"];
}

}  // namespace longterm_mapper2d
