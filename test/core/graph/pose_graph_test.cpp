#include "longterm_mapper2d/core/graph/pose_graph.h"

#include <gtest/gtest.h>

#include <cmath>

namespace longterm_mapper2d {
namespace {

TEST(PoseGraph, ANonFiniteGatingInformationIsRefused) {
  PoseGraph graph;
  for (GraphNodeId id : {0, 1}) {
    GraphNode node;
    node.id = id;
    node.pose = Pose2(id, 0.0, 0.0);
    ASSERT_TRUE(graph.AddNode(node).ok());
  }
  GraphEdge edge;
  edge.from = 0;
  edge.to = 1;
  edge.measurement = Pose2(1.0, 0.0, 0.0);
  edge.information = Eigen::Matrix3d::Identity() * 100.0;
  edge.gating_information = Eigen::Matrix3d::Constant(std::nan(""));
  EXPECT_FALSE(graph.AddEdge(edge).ok());  // like a non-finite information
  edge.gating_information = Eigen::Matrix3d::Identity();
  EXPECT_TRUE(graph.AddEdge(edge).ok());
}

}  // namespace
}  // namespace longterm_mapper2d
