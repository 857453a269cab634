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

}  // namespace test_support
}  // namespace longterm_mapper2d
