#include "testing/pose_graphs.h"

#include <gtest/gtest.h>

namespace longterm_mapper2d {
namespace test_support {

PoseGraph NodesAt(const std::map<GraphNodeId, Pose2>& poses) {
  PoseGraph graph;
  for (const auto& [id, pose] : poses) {
    GraphNode node;
    node.id = id;
    node.pose = pose;
    EXPECT_TRUE(graph.AddNode(node).ok());
  }
  return graph;
}

PoseGraph OdometryGraph(const std::map<GraphNodeId, Pose2>& poses,
                        const std::vector<std::pair<GraphNodeId, GraphNodeId>>& odometry,
                        const Eigen::Vector3d& information) {
  PoseGraph graph = NodesAt(poses);
  for (const auto& [from, to] : odometry) {
    GraphEdge edge;
    edge.from = from;
    edge.to = to;
    edge.measurement = poses.at(from).Between(poses.at(to));
    edge.information = information.asDiagonal();
    edge.kind = EdgeKind::kOdometry;
    EXPECT_TRUE(graph.AddEdge(edge).ok());
  }
  return graph;
}

}  // namespace test_support
}  // namespace longterm_mapper2d
