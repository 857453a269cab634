// Long-term maintenance of the Mapper (ALGORITHMS.md §9): merging local maps that a loop closure
// joined, removing the older node, condensing its edges.
#include <algorithm>
#include <limits>
#include <map>
#include <set>

#include "longterm_mapper2d/core/graph/condensation.h"
#include "longterm_mapper2d/core/graph/edge_pruning.h"
#include "longterm_mapper2d/core/graph/optimizer.h"
#include "longterm_mapper2d/core/mapping/mapper.h"
#include "longterm_mapper2d/core/mapping/merge_extent.h"
#include "longterm_mapper2d/core/mapping/waypoint_thinning.h"

namespace longterm_mapper2d {

void Mapper::QueueMerges(const std::vector<GraphEdge>& closures) {
  if (!options_.maintenance.enabled) return;
  for (const GraphEdge& edge : closures) {
    merge_queue_.emplace_back(std::min(edge.from, edge.to), std::max(edge.from, edge.to));
  }
}

void Mapper::MergeReadySets() {
  if (merge_queue_.empty()) return;
  // Connected sets of queued pairs.
  std::map<NodeId, NodeId> parent;
  auto find = [&parent](NodeId x) {
    while (parent.at(x) != x) x = parent[x] = parent.at(parent.at(x));
    return x;
  };
  for (const auto& [a, b] : merge_queue_) {
    parent.emplace(a, a);
    parent.emplace(b, b);
    parent[find(a)] = find(b);
  }
  std::map<NodeId, std::vector<NodeId>> sets;
  for (const auto& [id, unused] : parent) sets[find(id)].push_back(id);
  // A set waits while a pending candidate still votes on one of its nodes, and while its newest
  // node is younger than MaintenanceOptions::merge_delay_nodes.
  std::set<NodeId> referenced;
  for (const ClosureCandidate& c : loop_closer_.buffer()) {
    referenced.insert(c.local);
    referenced.insert(c.old);
  }
  std::vector<std::pair<NodeId, NodeId>> waiting;
  const auto merges_before = stats_.counters["merges"];
  for (auto& [root, ids] : sets) {
    const bool young = !finishing_ && last_node_ &&
                       *last_node_ - ids.back() < options_.maintenance.merge_delay_nodes;
    const bool busy = young || std::any_of(ids.begin(), ids.end(),
                                           [&](NodeId id) { return referenced.count(id) > 0; });
    if (busy) {
      for (const auto& pair : merge_queue_) {
        if (find(pair.first) == root) waiting.push_back(pair);
      }
      continue;
    }
    std::vector<NodeId> present;
    for (NodeId id : ids) {
      if (nodes_.count(id)) present.push_back(id);
    }
    // Members too far from the survivor stay nodes of their own; their pairs leave the queue.
    const std::vector<NodeId> within =
        MergeMembersWithinExtent(nodes_, present, options_.maintenance.merge_max_extent_m);
    if (within.size() < present.size()) {
      stats_.counters["merge_members_beyond_extent"] += present.size() - within.size();
    }
    if (within.size() >= 2) MergeSet(within);  // ids come sorted from the map
  }
  merge_queue_ = std::move(waiting);
  merge_queue_.insert(merge_queue_.end(), requeued_merges_.begin(), requeued_merges_.end());
  requeued_merges_.clear();
  if (options_.maintenance.drop_waypoints_seen_again && stats_.counters["merges"] > merges_before) {
    stats_.counters["waypoints_dropped_seen_again"] +=
        DropWaypointsSeenAgain(&nodes_, options_.maintenance.waypoint_merge_distance_m,
                               options_.maintenance.waypoint_merge_angle_rad);
  }
}

void Mapper::MergeSet(const std::vector<NodeId>& ids) {
  ScopedStageTimer timer(stats_.stage_times, "maintenance");
  OptimizeGraph(options_.maintenance.optimizer_iterations);
  const std::set<NodeId> members(ids.begin(), ids.end());
  // A closure the optimised graph cannot satisfy is an outlier the vote let through: it leaves
  // the graph (so it neither pulls the map nor lingers across sessions), and the pairs whose
  // closures hold are merged on a later pass.
  auto& edges = graph_.mutable_edges();
  const auto before = edges.size();
  edges.erase(std::remove_if(edges.begin(), edges.end(),
                             [&](const GraphEdge& edge) {
                               return edge.kind == EdgeKind::kLoopClosure &&
                                      members.count(edge.from) && members.count(edge.to) &&
                                      EdgeChi2(graph_, edge) >
                                          options_.maintenance.max_closure_chi2;
                             }),
              edges.end());
  if (edges.size() != before) {
    stats_.counters["loop_closures_removed_inconsistent"] += before - edges.size();
    ++stats_.counters["merges_refused_inconsistent"];
    for (const GraphEdge& edge : edges) {
      if (edge.kind == EdgeKind::kLoopClosure && members.count(edge.from) &&
          members.count(edge.to)) {
        requeued_merges_.emplace_back(std::min(edge.from, edge.to), std::max(edge.from, edge.to));
      }
    }
    OptimizeGraph(options_.maintenance.optimizer_iterations);
    return;
  }
  const NodeId survivor = ids.back();
  const std::vector<NodeId> removed(ids.begin(), ids.end() - 1);

  // The graph first: if condensation refuses, nothing has changed.
  const CondensationMode mode = *CondensationModeFromName(options_.maintenance.condensation);
  PoseGraph graph = graph_;
  const auto report = RemoveNodesCondensed(graph, removed, survivor, mode, session_id_,
                                           nodes_.at(survivor).stamp_s);
  if (!report.ok()) {
    ++stats_.counters["merges_refused"];
    return;
  }
  // Oldest first, so the newest node ends up holding everything ("new overwrites old").
  for (std::size_t i = 0; i + 1 < ids.size(); ++i) {
    LocalMapNode& newer = nodes_.at(ids[i + 1]);
    const LocalMapNode& older = nodes_.at(ids[i]);
    const LocalMapMergeStats merged =
        local_map_merger_.Merge(older, newer.map_T_node.Between(older.map_T_node), &newer);
    stats_.counters["merge_virtual_scans"] += merged.virtual_scans;
    stats_.counters["merge_virtual_scans_aligned"] += merged.aligned;
    stats_.counters["merge_points_erased"] += merged.merge.erased + merged.merge.replaced;
  }
  // Scans of the removed stretches now hang off the survivor, where the graph put them; so do
  // those of earlier sessions, through the removed nodes' record.
  const Pose2& map_T_survivor = nodes_.at(survivor).map_T_node;
  const std::set<NodeId> gone(removed.begin(), removed.end());
  for (TrajectoryEntry& entry : trajectory_) {
    if (!entry.attached || !gone.count(entry.node)) continue;
    const Pose2 survivor_T_removed = map_T_survivor.Between(nodes_.at(entry.node).map_T_node);
    entry.pose = survivor_T_removed * entry.pose;
    if (entry.refined) entry.refined = survivor_T_removed * *entry.refined;
    entry.node = survivor;
  }
  for (auto& [id, record] : removed_nodes_) {
    if (!gone.count(record.survivor)) continue;
    record.survivor_T_removed =
        map_T_survivor.Between(nodes_.at(record.survivor).map_T_node) * record.survivor_T_removed;
    record.survivor = survivor;
  }
  for (NodeId id : removed) {
    removed_nodes_[id] = {survivor, map_T_survivor.Between(nodes_.at(id).map_T_node)};
  }
  // The survivor inherits the frame anchor of the oldest removed node that had one (unless it has
  // its own), moved by the pair's relative pose as the graph has it: anchored where that node
  // was anchored, not where it has drifted to.
  if (!frame_anchors_.count(survivor)) {
    for (NodeId id : removed) {
      const auto anchor = frame_anchors_.find(id);
      if (anchor == frame_anchors_.end()) continue;
      frame_anchors_[survivor] = anchor->second * nodes_.at(id).map_T_node.Between(map_T_survivor);
      break;
    }
  }
  for (NodeId id : removed) {
    nodes_.erase(id);
    tracker_T_node_.erase(id);
    frame_anchors_.erase(id);
  }
  edges_.erase(std::remove_if(edges_.begin(), edges_.end(),
                              [&](const OdometryEdge& e) {
                                return gone.count(e.from) > 0 || gone.count(e.to) > 0;
                              }),
               edges_.end());
  graph_ = std::move(graph);
  stats_.counters["condensed_edges_pruned"] +=
      PruneNegligibleCondensedEdges(&graph_, options_.maintenance.prune_edge_ratio);
  ++stats_.counters["merges"];
  stats_.counters["nodes_removed"] += removed.size();
  stats_.counters["condensed_edges_added"] += report.value().added_edges;
  stats_.counters["condensed_edges_fused"] += report.value().fused_edges;
  stats_.counters["condensed_edges_composed"] += report.value().composed_edges;
  stats_.counters["nodes"] = nodes_.size();
  OptimizeGraph(options_.maintenance.optimizer_iterations);
}

void Mapper::CleanFinishedNode() {
  // The pending waypoints are the stretch since the last node, placed in the tracker frame of the
  // nodes before it as long as the tracker did not fail on the way (after a failure odometry
  // placed the scans: no free-space claims from them).
  const TrackerOptions& tracker = options_.tracker;
  const int max_nodes = std::max(tracker.clean_finished_nodes, tracker.clean_moved_nodes);
  if (max_nodes <= 0 || !options_.merger.free_space_reasoning || !last_node_ ||
      stretch_after_failure_ || pending_waypoints_.empty()) {
    return;
  }
  std::vector<NodeId> finished = {*last_node_};
  for (auto e = edges_.rbegin();
       e != edges_.rend() && static_cast<int>(finished.size()) < max_nodes; ++e) {
    if (e->to != finished.back() || e->after_tracker_failure) break;
    finished.push_back(e->from);
  }
  int erased = 0;
  for (std::size_t back = 0; back < finished.size(); ++back) {
    const auto node = nodes_.find(finished[back]);
    const auto tracker_T_node = tracker_T_node_.find(finished[back]);
    if (node == nodes_.end() || tracker_T_node == tracker_T_node_.end()) continue;
    // Older nodes lose only what was seen moving: their wall points, seen from farther along the
    // route at grazing angles, are what later alignments with them rest on.
    const int max_observations =
        static_cast<int>(back) < tracker.clean_finished_nodes ? std::numeric_limits<int>::max() : 0;
    const Pose2 node_T_tracker = tracker_T_node->second.inverse();
    for (const PendingWaypoint& w : pending_waypoints_) {
      erased += node_cleaner_.EraseSeenThrough(node->second.cloud, w.scan,
                                               node_T_tracker * w.tracker_T_base * w.base_T_laser,
                                               max_observations);
    }
  }
  stats_.counters["finished_node_points_erased"] += erased;
}

}  // namespace longterm_mapper2d
