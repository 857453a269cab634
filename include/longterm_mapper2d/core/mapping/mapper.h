#pragma once

#include <deque>
#include <map>
#include <optional>
#include <vector>

#include "longterm_mapper2d/core/cloud/cloud_merger.h"
#include "longterm_mapper2d/core/config/mapper_options.h"
#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/graph/pose_graph.h"
#include "longterm_mapper2d/core/loop_closing/loop_closer.h"
#include "longterm_mapper2d/core/map/session_map_file.h"
#include "longterm_mapper2d/core/map/trajectory_anchors.h"
#include "longterm_mapper2d/core/mapping/local_map.h"
#include "longterm_mapper2d/core/mapping/local_map_merger.h"
#include "longterm_mapper2d/core/mapping/mapper_stats.h"
#include "longterm_mapper2d/core/mapping/tracker.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d {

// What happened to one input scan.
enum class ScanOutcome { kProcessed, kSkipped };

// Mapping: the map grows and is maintained. Localization: the map is frozen and the robot is
// tracked against it.
enum class MapperMode { kMapping, kLocalization };
const char* MapperModeName(MapperMode mode);

// The façade of the core: everything the ROS node and the offline tools call. Feed it scans with
// their odometry in time order; ask it for poses, the map and statistics.
//
// Scans are tracked against a local map (Tracker); every 2.5 m / 1 rad (or on tracker failure) the
// stretch becomes a node: a local map with its waypoints, joined to the previous node by an
// odometry edge. Every input scan's pose is kept relative to its node, so the trajectory follows
// later corrections of the node poses.
class Mapper {
 public:
  explicit Mapper(const MapperOptions& options);

  const MapperOptions& options() const { return options_; }

  // Adds one scan. Every scan, processed or skipped, gets a pose in the trajectory.
  ScanOutcome AddScan(const ScanInput& input);

  // Ends the session: the open stretch becomes the last node, the final closure check runs, and
  // the trajectory is refined against the finished map (RefineTrajectory).
  void Finish();
  // What Finish() does to the graph, without ending the session: a last vote on the pending
  // loop-closure candidates, the final sweep (every node of this session searched again from the
  // optimised graph, LoopClosingOptions::final_sweep), then the whole graph optimised (up to the
  // optimizer's iteration limit). Refused in localization mode (the map is frozen); an error if the
  // solve was unusable (the estimate is kept).
  Status OptimizeNow();
  // Aligns the session's waypoint scans once more with the local maps at their current poses and
  // places every scan of the trajectory by the corrections around it
  // (TrajectoryRefinementOptions). Finish() and OptimizeNow() call it; later corrections of the
  // graph carry the refined poses with their nodes.
  void RefineTrajectory();

  // Starts this mapper as a new session on top of a saved map, before the first scan. The robot
  // is at `initial_pose` in the loaded map's frame at the first scan (default: where the map's
  // first session started, the docking-station case). Node ids continue.
  Status LoadSession(const SessionMap& map, const std::optional<Pose2>& initial_pose);
  // Switches between mapping and localization at any time. Localization needs a map (loaded or
  // mapped so far); the open stretch becomes a node first, so nothing mapped is lost. Back in
  // mapping, the next scan starts a node tied to the map node nearest to the robot.
  Status SetMode(MapperMode mode);
  MapperMode mode() const { return mode_; }

  // Everything a later session needs (call after Finish()).
  SessionMap ExportSession() const;
  int session_id() const { return session_id_; }

  // map_T_base for every input scan, in input order, at the final estimate; the scans that hang off
  // local maps smoothed across their boundaries (TrajectorySmoothingOptions).
  std::vector<StampedPose2> Trajectory() const;
  // The same poses as they hang off the local maps (the scans after the last node off it): a
  // later session's map re-expresses them with every correction since (ReexpressTrajectory).
  std::vector<AnchoredPose> TrajectoryAnchors() const;
  // The latest estimate of map_T_odom (what the node publishes on TF).
  Pose2 map_T_odom() const { return map_T_odom_; }
  // The raw scans kept as waypoints, placed in the map at the current estimate.
  std::vector<PosedScan> WaypointScans() const;
  // Nodes by id, and the odometry edges between consecutive nodes.
  const std::map<NodeId, LocalMapNode>& nodes() const { return nodes_; }
  const std::vector<OdometryEdge>& edges() const { return edges_; }
  // The pose graph over the nodes: odometry edges and accepted loop closures.
  const PoseGraph& graph() const { return graph_; }
  // The tracker's current local map, in the map frame.
  Cloud LocalMapInMap() const;

  const MapperStats& stats() const { return stats_; }

 private:
  struct TrajectoryEntry {
    double stamp_s = 0.0;
    bool attached = false;
    bool in_map = false;  // recorded in localization: the pose is map_T_base, fixed
    NodeId node = 0;
    Pose2 pose;            // node_T_base if attached, map_T_base if in_map, else tracker_T_base
    Pose2 tracker_T_base;  // as the tracker had it (the chain the trajectory is smoothed along)
    std::optional<Pose2> refined;  // node_T_base as RefineTrajectory aligned the scan, if it did
  };
  // A waypoint's scan kept for RefineTrajectory, with the trajectory entry it belongs to.
  struct RefinementScan {
    std::size_t entry = 0;
    Pose2 base_T_laser;
    LaserScan scan;
  };
  struct PendingWaypoint {
    Pose2 tracker_T_base;
    Pose2 base_T_laser;
    LaserScan scan;
  };

  void Record(double stamp_s, const Pose2& tracker_T_base, const Pose2& odom_T_base);
  void MaybeAddWaypoint(const ScanInput& input, const Pose2& tracker_T_base);
  void CreateNode(double stamp_s, const Pose2& tracker_T_base, bool after_failure);
  void CleanFinishedNode();
  // Loop closing for a new node, then optimisation if closures were accepted.
  // Loop closing for a new node (mapper_loop_closing.cpp): search, vote, accepted closures in.
  void CloseLoops(NodeId node, bool force);
  // Edges for the closures the vote accepted, then an optimisation and the merges they allow.
  void AcceptClosures(const std::vector<GraphEdge>& closures);
  // The last vote on pending candidates, the final sweep (LoopClosingOptions::final_sweep) and a
  // full optimisation: what Finish() and OptimizeNow() do to the graph.
  void FinalClosureCheck();
  // Every node of this session searched again, oldest first, from the optimised graph.
  void SweepClosures();
  void OptimizeGraph(int max_iterations);
  // Long-term maintenance (mapper_maintenance.cpp): pairs joined by accepted closures wait in a
  // queue until no pending closure candidate touches them; then each connected set merges into
  // its newest node and the older nodes are removed with condensed edges.
  void QueueMerges(const std::vector<GraphEdge>& closures);
  void MergeReadySets();
  void MergeSet(const std::vector<NodeId>& ids);
  // Localization (mapper_localization.cpp): aligns the tracker's local map to the map.
  void MaybeLocalize(const Pose2& tracker_T_base);
  // map_T_tracker for the open stretch (the last node's correction applies to it).
  Pose2 MapTTracker() const;

  MapperOptions options_;
  MapperStats stats_;
  MapperMode mode_ = MapperMode::kMapping;
  Pose2 localization_map_T_tracker_;
  Pose2 last_localization_tracker_T_base_;
  Tracker tracker_;
  Pose2 map_T_odom_;
  int session_id_ = 0;
  // Before this session's first node: where the tracker frame sits in the map (set from the
  // initial pose at the first processed scan), and the loaded node the session links to.
  std::optional<Pose2> initial_map_T_base_;
  Pose2 map_T_tracker_start_;
  std::optional<NodeId> session_anchor_;
  // Where the first session of the map started (SessionMap::origin), held by a node: the first
  // node, or on a loaded map the node nearest to the loaded origin; once that node is merged
  // away, its survivor (removed_nodes_). The origin so follows the optimised map: a fixed
  // map-frame pose does not, once the gauge has left the start (intel: 0.2-0.65 m off along the
  // start corridor after one session, and later sessions started there).
  std::optional<NodeId> origin_node_;
  Pose2 node_T_origin_;
  Pose2 OriginInMap() const;
  // The node whose origin is nearest to the pose's position (nodes_ must not be empty).
  NodeId NearestNode(const Pose2& map_T_pose) const;

  // Tracking state.
  bool has_last_processed_ = false;
  double last_processed_stamp_s_ = 0.0;
  Pose2 last_odom_T_base_;     // at the last processed scan
  Pose2 last_tracker_T_base_;  // at the last processed scan
  std::optional<Pose2> last_waypoint_tracker_T_base_;
  // Where the current stretch began: where the last node was made, or the first scan of a stretch
  // with no node before it (a session's first, or the first after localization). The next node is
  // made node_translation_m / node_rotation_rad from here. A stretch with no node before it makes
  // its node at its end like any other, but in the frame of its start: the session's start stays
  // a node (the gauge, the origin, the initial pose) and that node holds the whole first stretch.
  // Made at the first scan, it held that one scan (a view along intel's docking corridor, which no
  // closure aligned with), and every session left one more such node behind.
  std::optional<Pose2> tracker_T_stretch_start_;
  Eigen::Matrix3d stretch_covariance_ = Eigen::Matrix3d::Zero();         // since the last node
  Eigen::Matrix3d stretch_gating_covariance_ = Eigen::Matrix3d::Zero();  // ... for the gate
  bool stretch_after_failure_ = false;
  // The first node after a tracker failure, until a closure ties a node from it on to an older
  // node: the heading of those nodes may be far off, so their closures are searched wider.
  std::optional<NodeId> doubtful_since_;

  // Graph state: nodes, their tracker poses, edges, and the nodes merged away (of every session).
  std::map<NodeId, LocalMapNode> nodes_;
  std::map<NodeId, RemovedNode> removed_nodes_;
  std::map<NodeId, Pose2> tracker_T_node_;
  // Where the loaded map had each node of earlier sessions (map_T_node): with
  // maintenance.hold_loaded_frame, each optimisation's solution is moved rigidly to match them
  // (FrameCorrection) instead of the map frame hanging on the gauge node; a merge hands a removed
  // node's anchor on to the survivor (see MergeSet).
  std::map<NodeId, Pose2> frame_anchors_;
  std::vector<OdometryEdge> edges_;
  PoseGraph graph_;
  LoopCloser loop_closer_;
  LocalMapMerger local_map_merger_;
  CloudMerger node_cleaner_;
  std::vector<std::pair<NodeId, NodeId>> merge_queue_;
  // Set during FinalClosureCheck: queued merges no longer wait for younger nodes.
  bool finishing_ = false;
  // Pairs whose merge set lost an inconsistent closure, merged on the next pass.
  std::vector<std::pair<NodeId, NodeId>> requeued_merges_;
  NodeId next_node_id_ = 0;
  std::optional<NodeId> last_node_;

  std::vector<TrajectoryEntry> trajectory_;
  std::size_t first_pending_entry_ = 0;
  std::vector<PendingWaypoint> pending_waypoints_;
  std::deque<RefinementScan> refinement_scans_;  // this session's, oldest first
};

}  // namespace longterm_mapper2d
