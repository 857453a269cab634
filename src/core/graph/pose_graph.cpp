#include "longterm_mapper2d/core/graph/pose_graph.h"

#include <algorithm>

namespace longterm_mapper2d {

const char* EdgeKindName(EdgeKind kind) {
  switch (kind) {
    case EdgeKind::kOdometry: return "odometry";
    case EdgeKind::kLoopClosure: return "loop_closure";
    case EdgeKind::kCondensed: return "condensed";
  }
  return "unknown";
}

Status PoseGraph::AddNode(const GraphNode& node) {
  if (nodes_.count(node.id)) return Status::Error("node " + std::to_string(node.id) + " exists");
  if (!node.pose.IsFinite()) return Status::Error("node " + std::to_string(node.id) + " pose is not finite");
  nodes_.emplace(node.id, node);
  if (!gauge_) gauge_ = node.id;
  return Status::Ok();
}

Status PoseGraph::AddEdge(const GraphEdge& edge) {
  if (!nodes_.count(edge.from) || !nodes_.count(edge.to)) {
    return Status::Error("edge " + std::to_string(edge.from) + " -> " + std::to_string(edge.to) +
                         " refers to a missing node");
  }
  if (edge.from == edge.to) return Status::Error("edge joins node " + std::to_string(edge.from) + " to itself");
  if (!edge.measurement.IsFinite() || !edge.information.allFinite() ||
      (edge.gating_information && !edge.gating_information->allFinite())) {
    return Status::Error("edge " + std::to_string(edge.from) + " -> " + std::to_string(edge.to) +
                         " is not finite");
  }
  edges_.push_back(edge);
  return Status::Ok();
}

void PoseGraph::RemoveNode(GraphNodeId id) {
  if (!nodes_.erase(id)) return;
  edges_.erase(std::remove_if(edges_.begin(), edges_.end(),
                              [id](const GraphEdge& e) { return e.from == id || e.to == id; }),
               edges_.end());
  if (gauge_ == id) {
    gauge_.reset();
    if (!nodes_.empty()) gauge_ = nodes_.rbegin()->first;
  }
}

std::vector<std::size_t> PoseGraph::EdgesOf(GraphNodeId id) const {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < edges_.size(); ++i) {
    if (edges_[i].from == id || edges_[i].to == id) out.push_back(i);
  }
  return out;
}

std::optional<std::size_t> PoseGraph::FindEdge(GraphNodeId a, GraphNodeId b) const {
  for (std::size_t i = 0; i < edges_.size(); ++i) {
    if ((edges_[i].from == a && edges_[i].to == b) || (edges_[i].from == b && edges_[i].to == a)) {
      return i;
    }
  }
  return std::nullopt;
}

Status PoseGraph::SetGauge(GraphNodeId id) {
  if (!nodes_.count(id)) return Status::Error("gauge node " + std::to_string(id) + " is missing");
  gauge_ = id;
  return Status::Ok();
}

}  // namespace longterm_mapper2d
