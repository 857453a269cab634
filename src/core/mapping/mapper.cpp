#include "longterm_mapper2d/core/mapping/mapper.h"

#include <Eigen/Dense>
#include <Eigen/LU>
#include <cmath>
#include <limits>

#include "longterm_mapper2d/core/graph/frame_anchor.h"
#include "longterm_mapper2d/core/graph/optimizer.h"

namespace longterm_mapper2d {

Mapper::Mapper(const MapperOptions& options)
    : options_(options),
      tracker_(options),
      loop_closer_(options.loop_closing, options.registration),
      local_map_merger_(options.maintenance, options.merger, options.registration,
                        options.cloud.max_range_m),
      node_cleaner_(options.merger) {}

Pose2 Mapper::MapTTracker() const {
  if (mode_ == MapperMode::kLocalization) return localization_map_T_tracker_;
  if (!last_node_) return map_T_tracker_start_;
  return nodes_.at(*last_node_).map_T_node * tracker_T_node_.at(*last_node_).inverse();
}

void Mapper::Record(double stamp_s, const Pose2& tracker_T_base, const Pose2& odom_T_base) {
  if (mode_ == MapperMode::kLocalization) {
    trajectory_.push_back(
        {stamp_s, false, true, 0, MapTTracker() * tracker_T_base, tracker_T_base, std::nullopt});
  } else {
    trajectory_.push_back({stamp_s, false, false, 0, tracker_T_base, tracker_T_base, std::nullopt});
  }
  map_T_odom_ = MapTTracker() * tracker_T_base * odom_T_base.inverse();
}

ScanOutcome Mapper::AddScan(const ScanInput& input) {
  if (input.scan.angle_increment_rad < 0.0) {
    ScanInput counter_clockwise = input;
    counter_clockwise.scan.MakeCounterClockwise();
    ++stats_.counters["scans_reversed"];
    return AddScan(counter_clockwise);
  }
  ++stats_.scans_received;
  const Pose2 odometry_step =
      has_last_processed_ ? last_odom_T_base_.Between(input.odom_T_base) : Pose2();
  // Until the first processed scan, the tracker frame is the odometry frame.
  const Pose2 dead_reckoned =
      has_last_processed_ ? last_tracker_T_base_ * odometry_step : input.odom_T_base;

  auto skip = [&](const char* reason) {
    ++stats_.scans_skipped[reason];
    Record(input.scan.stamp_s, dead_reckoned, input.odom_T_base);
    return ScanOutcome::kSkipped;
  };
  if (!input.odom_T_base.IsFinite() || !input.base_T_laser.IsFinite()) {
    // Without a pose the scan cannot be placed at all.
    ++stats_.scans_skipped["non_finite_pose"];
    if (has_last_processed_) Record(input.scan.stamp_s, last_tracker_T_base_, last_odom_T_base_);
    return ScanOutcome::kSkipped;
  }
  if (!input.scan.ValidateGeometry().ok()) return skip("invalid_geometry");
  if (has_last_processed_ && input.scan.stamp_s < last_processed_stamp_s_) {
    // A looped bag or a clock reset: the scan cannot follow the last one in time.
    return skip("time_backwards");
  }
  if (static_cast<int>(input.scan.ranges.size()) < options_.input.min_beams) {
    return skip("too_few_beams");
  }
  if (has_last_processed_ &&
      odometry_step.translation().norm() < options_.tracker.min_translation_m &&
      std::abs(odometry_step.theta()) < options_.tracker.min_rotation_rad) {
    // A copy of the last processed scan (same stamp) keeps its pose: one time, one pose.
    if (options_.tracker.locate_skipped_scans && input.scan.stamp_s > last_processed_stamp_s_) {
      const std::optional<Pose2> located =
          tracker_.Locate(input, last_tracker_T_base_, odometry_step, stats_);
      if (located) {
        ++stats_.scans_skipped["no_motion"];
        Record(input.scan.stamp_s, *located, input.odom_T_base);
        return ScanOutcome::kSkipped;
      }
    }
    return skip("no_motion");
  }

  Pose2 tracker_T_base = dead_reckoned;
  bool failed = false;
  if (!has_last_processed_ && initial_map_T_base_) {
    // The tracker frame is the odometry frame; place it so the robot starts at the initial pose.
    map_T_tracker_start_ = *initial_map_T_base_ * tracker_T_base.inverse();
    localization_map_T_tracker_ = map_T_tracker_start_;
    last_localization_tracker_T_base_ = tracker_T_base;
  }
  if (!tracker_.initialized()) {
    tracker_.Reset(input, tracker_T_base, stats_);
  } else {
    const TrackResult tracked = tracker_.Track(input, last_tracker_T_base_, odometry_step, stats_);
    tracker_T_base = tracked.tracker_T_base;
    failed = tracked.failed;
    // Accumulate the stretch covariance: node_T_current = node_T_previous * step.
    const Pose2 tracker_T_node =
        last_node_ ? tracker_T_node_.at(*last_node_) : tracker_T_stretch_start_.value_or(Pose2());
    const Pose2 node_T_previous = tracker_T_node.Between(last_tracker_T_base_);
    const Pose2 step = last_tracker_T_base_.Between(tracker_T_base);
    const Eigen::Matrix3d j1 = ComposeJacobianLeft(node_T_previous, step);
    const Eigen::Matrix3d j2 = ComposeJacobianRight(node_T_previous, step);
    stretch_covariance_ =
        j1 * stretch_covariance_ * j1.transpose() + j2 * tracked.step_covariance * j2.transpose();
    stretch_gating_covariance_ = j1 * stretch_gating_covariance_ * j1.transpose() +
                                 j2 * tracked.gating_step_covariance * j2.transpose();
    stretch_after_failure_ |= failed;
  }
  ++stats_.scans_processed;
  has_last_processed_ = true;
  last_processed_stamp_s_ = input.scan.stamp_s;
  last_odom_T_base_ = input.odom_T_base;
  last_tracker_T_base_ = tracker_T_base;
  Record(input.scan.stamp_s, tracker_T_base, input.odom_T_base);
  if (mode_ == MapperMode::kLocalization) {
    MaybeLocalize(tracker_T_base);
    return ScanOutcome::kProcessed;
  }
  MaybeAddWaypoint(input, tracker_T_base);

  if (!tracker_T_stretch_start_) {
    tracker_T_stretch_start_ = tracker_T_base;
    return ScanOutcome::kProcessed;
  }
  const Pose2 since_start = tracker_T_stretch_start_->Between(tracker_T_base);
  if (failed || since_start.translation().norm() >= options_.tracker.node_translation_m ||
      std::abs(since_start.theta()) >= options_.tracker.node_rotation_rad) {
    CreateNode(input.scan.stamp_s, tracker_T_base, stretch_after_failure_);
  }
  return ScanOutcome::kProcessed;
}

void Mapper::MaybeAddWaypoint(const ScanInput& input, const Pose2& tracker_T_base) {
  if (last_waypoint_tracker_T_base_) {
    const Pose2 moved = last_waypoint_tracker_T_base_->Between(tracker_T_base);
    if (moved.translation().norm() < options_.input.waypoint_spacing_m &&
        std::abs(moved.theta()) < options_.input.waypoint_spacing_rad) {
      return;
    }
  }
  last_waypoint_tracker_T_base_ = tracker_T_base;
  pending_waypoints_.push_back({tracker_T_base, input.base_T_laser, input.scan});
  const TrajectoryRefinementOptions& refinement = options_.trajectory_refinement;
  if (refinement.enabled && refinement.max_scans > 0) {
    // The scan's entry is the last one recorded (AddScan records before it adds the waypoint).
    refinement_scans_.push_back({trajectory_.size() - 1, input.base_T_laser, input.scan});
    if (refinement_scans_.size() > static_cast<std::size_t>(refinement.max_scans)) {
      refinement_scans_.pop_front();
    }
  }
}

void Mapper::CreateNode(double stamp_s, const Pose2& tracker_T_base, bool after_failure) {
  LocalMapNode node;
  node.id = next_node_id_++;
  node.session_id = session_id_;
  node.stamp_s = stamp_s;
  // The first node of a chain stands at its stretch's start (see tracker_T_stretch_start_).
  const bool first_of_chain = !last_node_;
  const Pose2 tracker_T_node =
      first_of_chain ? tracker_T_stretch_start_.value_or(tracker_T_base) : tracker_T_base;
  node.map_T_node = MapTTracker() * tracker_T_node;
  if (!origin_node_) {
    origin_node_ = node.id;
    node_T_origin_ = Pose2();
  }
  CleanFinishedNode();
  const Pose2 node_T_tracker = tracker_T_node.inverse();
  node.cloud = Transform(node_T_tracker, tracker_.local_map());
  for (PendingWaypoint& w : pending_waypoints_) {
    node.waypoints.push_back(
        {node_T_tracker * w.tracker_T_base, w.base_T_laser, std::move(w.scan), session_id_});
  }
  pending_waypoints_.clear();
  for (std::size_t i = first_pending_entry_; i < trajectory_.size(); ++i) {
    if (trajectory_[i].in_map) continue;
    trajectory_[i].pose = node_T_tracker * trajectory_[i].pose;
    trajectory_[i].attached = true;
    trajectory_[i].node = node.id;
  }
  first_pending_entry_ = trajectory_.size();

  if (last_node_) {
    OdometryEdge edge;
    edge.from = *last_node_;
    edge.to = node.id;
    edge.from_T_to = tracker_T_node_.at(*last_node_).Between(tracker_T_node);
    // A stretch of skipped scans only has no motion and no uncertainty; keep it invertible.
    const auto information = [](const Eigen::Matrix3d& covariance) {
      const Eigen::Matrix3d inverse = (covariance + 1e-9 * Eigen::Matrix3d::Identity()).inverse();
      return Eigen::Matrix3d(0.5 * (inverse + inverse.transpose()));
    };
    edge.information = information(stretch_covariance_);
    if (options_.tracker.tight_odometry_edges) {
      edge.gating_information = information(stretch_gating_covariance_);
    }
    edge.after_tracker_failure = after_failure;
    edges_.push_back(edge);
  }
  // What the tracker accumulated runs on from the node's frame: a chain's first node stands at its
  // stretch's start, so that stretch is part of the next edge.
  if (!first_of_chain) {
    stretch_covariance_.setZero();
    stretch_gating_covariance_.setZero();
    stretch_after_failure_ = false;
  }
  if (after_failure && !doubtful_since_) doubtful_since_ = node.id;
  tracker_T_node_[node.id] = tracker_T_node;
  tracker_T_stretch_start_ = tracker_T_base;
  last_node_ = node.id;
  GraphNode graph_node;
  graph_node.id = node.id;
  graph_node.pose = node.map_T_node;
  graph_node.session_id = node.session_id;
  graph_node.stamp_s = node.stamp_s;
  graph_.AddNode(graph_node);
  if (!edges_.empty() && edges_.back().to == node.id) {
    GraphEdge edge;
    edge.from = edges_.back().from;
    edge.to = node.id;
    edge.measurement = edges_.back().from_T_to;
    edge.information = edges_.back().information;
    edge.gating_information = edges_.back().gating_information;
    edge.kind = EdgeKind::kOdometry;
    edge.session_id = session_id_;
    edge.stamp_s = node.stamp_s;
    graph_.AddEdge(edge);
  } else if (session_anchor_ && graph_.HasNode(*session_anchor_)) {
    // The first node of a session on a loaded map: tied to the map by the initial pose.
    GraphEdge link;
    link.from = *session_anchor_;
    link.to = node.id;
    link.measurement = graph_.node(*session_anchor_).pose.Between(node.map_T_node);
    const double s_xy = options_.session.initial_pose_sigma_m;
    const double s_th = options_.session.initial_pose_sigma_rad;
    link.information =
        Eigen::Vector3d(1.0 / (s_xy * s_xy), 1.0 / (s_xy * s_xy), 1.0 / (s_th * s_th)).asDiagonal();
    link.kind = EdgeKind::kOdometry;
    link.session_id = session_id_;
    link.stamp_s = node.stamp_s;
    graph_.AddEdge(link);
    session_anchor_.reset();
  }
  const NodeId id = node.id;
  nodes_.emplace(id, std::move(node));
  stats_.counters["nodes"] = nodes_.size();
  CloseLoops(id, false);
}

Status Mapper::OptimizeNow() {
  if (mode_ != MapperMode::kMapping) {
    return Status::Error("not in mapping mode: the map is frozen while localizing");
  }
  if (graph_.nodes().empty()) return Status::Error("nothing to optimise yet: the map has no node");
  const auto before = stats_.counters["optimizations_unusable"];
  FinalClosureCheck();
  if (stats_.counters["optimizations_unusable"] != before) {
    return Status::Error("the solve was unusable; the previous estimate is kept");
  }
  RefineTrajectory();
  return Status::Ok();
}

void Mapper::OptimizeGraph(int max_iterations) {
  ScopedStageTimer timer(stats_.stage_times, "optimization");
  OptimizerOptions options = options_.optimizer;
  options.max_iterations = max_iterations;
  const OptimizationSummary summary = Optimize(graph_, options);
  ++stats_.counters["optimizations"];
  if (!summary.usable) {
    ++stats_.counters["optimizations_unusable"];
    return;
  }
  if (options_.maintenance.hold_loaded_frame) {
    if (const auto correction = FrameCorrection(graph_, frame_anchors_)) {
      MoveFrame(graph_, *correction);
    }
  }
  for (auto& [id, node] : nodes_) node.map_T_node = graph_.node(id).pose;
}

void Mapper::Finish() {
  if (!has_last_processed_) return;
  if (!pending_waypoints_.empty()) {
    CreateNode(trajectory_.back().stamp_s, last_tracker_T_base_, stretch_after_failure_);
  }
  // A last vote on whatever closures are still pending, the final sweep, then a full optimisation
  // (not in localization: the map stays as it was).
  if (options_.loop_closing.enabled && mode_ == MapperMode::kMapping) FinalClosureCheck();
  // Scans after the last node (skipped ones) are attached to it.
  if (!last_node_) return;
  const Pose2 node_T_tracker = tracker_T_node_.at(*last_node_).inverse();
  for (std::size_t i = first_pending_entry_; i < trajectory_.size(); ++i) {
    if (trajectory_[i].in_map) continue;
    trajectory_[i].pose = node_T_tracker * trajectory_[i].pose;
    trajectory_[i].attached = true;
    trajectory_[i].node = *last_node_;
  }
  first_pending_entry_ = trajectory_.size();
  RefineTrajectory();
}

std::vector<PosedScan> Mapper::WaypointScans() const {
  std::vector<PosedScan> scans;
  for (const auto& [id, node] : nodes_) {
    for (const Waypoint& w : node.waypoints) {
      scans.push_back({node.map_T_node * w.node_T_base * w.base_T_laser, w.scan});
    }
  }
  const Pose2 map_T_tracker = MapTTracker();
  for (const PendingWaypoint& w : pending_waypoints_) {
    scans.push_back({map_T_tracker * w.tracker_T_base * w.base_T_laser, w.scan});
  }
  return scans;
}

Status Mapper::LoadSession(const SessionMap& map, const std::optional<Pose2>& initial_pose) {
  if (stats_.scans_received > 0 || !nodes_.empty()) {
    return Status::Error("a session map can only be loaded before the first scan");
  }
  if (map.nodes.empty()) return Status::Error("the session map has no nodes");
  PoseGraph graph;
  for (const auto& [id, node] : map.nodes) {
    GraphNode graph_node;
    graph_node.id = id;
    graph_node.pose = node.map_T_node;
    graph_node.session_id = node.session_id;
    graph_node.stamp_s = node.stamp_s;
    if (Status s = graph.AddNode(graph_node); !s.ok()) return s;
  }
  for (const GraphEdge& edge : map.edges) {
    if (Status s = graph.AddEdge(edge); !s.ok()) return s;
  }
  if (Status s = graph.SetGauge(map.gauge); !s.ok()) return s;
  graph_ = std::move(graph);
  nodes_ = map.nodes;
  removed_nodes_ = map.removed_nodes;
  frame_anchors_.clear();
  for (const auto& [id, node] : nodes_) frame_anchors_[id] = node.map_T_node;
  session_id_ = map.sessions;
  next_node_id_ = map.nodes.rbegin()->first + 1;
  origin_node_ = NearestNode(map.origin);
  node_T_origin_ = nodes_.at(*origin_node_).map_T_node.Between(map.origin);
  const Pose2 start = initial_pose ? *initial_pose : map.origin;
  initial_map_T_base_ = start;
  // The session hangs off the loaded node nearest to where it starts.
  session_anchor_ = NearestNode(start);
  stats_.counters["nodes"] = nodes_.size();
  return Status::Ok();
}

SessionMap Mapper::ExportSession() const {
  SessionMap map;
  map.sessions = session_id_ + 1;
  map.nodes = nodes_;
  map.edges = graph_.edges();
  map.gauge = graph_.gauge().value_or(nodes_.empty() ? 0 : nodes_.begin()->first);
  map.origin = OriginInMap();
  map.removed_nodes = removed_nodes_;
  return map;
}

NodeId Mapper::NearestNode(const Pose2& map_T_pose) const {
  NodeId nearest = nodes_.begin()->first;
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [id, node] : nodes_) {
    const double d = (node.map_T_node.translation() - map_T_pose.translation()).norm();
    if (d < best) {
      best = d;
      nearest = id;
    }
  }
  return nearest;
}

Pose2 Mapper::OriginInMap() const {
  if (!origin_node_) return Pose2();
  if (const auto node = nodes_.find(*origin_node_); node != nodes_.end()) {
    return node->second.map_T_node * node_T_origin_;
  }
  const RemovedNode& removed = removed_nodes_.at(*origin_node_);
  return nodes_.at(removed.survivor).map_T_node * removed.survivor_T_removed * node_T_origin_;
}

Cloud Mapper::LocalMapInMap() const { return Transform(MapTTracker(), tracker_.local_map()); }

}  // namespace longterm_mapper2d
