#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/geometry/pose2.h"

namespace longterm_mapper2d {

using GraphNodeId = std::int64_t;

enum class EdgeKind { kOdometry = 0, kLoopClosure = 1, kCondensed = 2 };
const char* EdgeKindName(EdgeKind kind);

struct GraphNode {
  GraphNodeId id = 0;
  Pose2 pose;  // map_T_node
  int session_id = 0;
  double stamp_s = 0.0;
};

// A relative-pose measurement from_T_to with its information matrix (x, y, theta order).
struct GraphEdge {
  GraphNodeId from = 0;
  GraphNodeId to = 0;
  Pose2 measurement;
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  // A looser information for the loop closer's candidate gate (marginals), if the edge has one;
  // the optimiser uses `information` (TrackerOptions::tight_odometry_edges).
  std::optional<Eigen::Matrix3d> gating_information;
  EdgeKind kind = EdgeKind::kOdometry;
  int session_id = 0;
  double stamp_s = 0.0;
};

// Nodes and edges of a 2D pose graph, and its gauge (the node held fixed). Iteration order is
// deterministic: nodes by id, edges in insertion order.
class PoseGraph {
 public:
  Status AddNode(const GraphNode& node);
  Status AddEdge(const GraphEdge& edge);
  // Removes the node and every edge touching it; a removed gauge moves to the newest node.
  void RemoveNode(GraphNodeId id);

  bool HasNode(GraphNodeId id) const { return nodes_.count(id) > 0; }
  const GraphNode& node(GraphNodeId id) const { return nodes_.at(id); }
  GraphNode& mutable_node(GraphNodeId id) { return nodes_.at(id); }
  const std::map<GraphNodeId, GraphNode>& nodes() const { return nodes_; }
  const std::vector<GraphEdge>& edges() const { return edges_; }
  std::vector<GraphEdge>& mutable_edges() { return edges_; }
  // Indices into edges() of the edges touching a node.
  std::vector<std::size_t> EdgesOf(GraphNodeId id) const;
  std::optional<std::size_t> FindEdge(GraphNodeId a, GraphNodeId b) const;

  // The fixed node: the first node added unless set.
  std::optional<GraphNodeId> gauge() const { return gauge_; }
  Status SetGauge(GraphNodeId id);

 private:
  std::map<GraphNodeId, GraphNode> nodes_;
  std::vector<GraphEdge> edges_;
  std::optional<GraphNodeId> gauge_;
};

}  // namespace longterm_mapper2d
