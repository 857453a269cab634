#include "longterm_mapper2d/core/graph/pose_graph.h"

#include <gtest/gtest.h>

#include <cmath>

namespace longterm_mapper2d {
namespace {

TEST(PoseGraph, TheGatingGraphCarriesTheEdgesGatingInformation) {
  PoseGraph graph;
  for (GraphNodeId id : {0, 1, 2}) {
    GraphNode node;
    node.id = id;
    node.pose = Pose2(id, 0.0, 0.0);
    ASSERT_TRUE(graph.AddNode(node).ok());
  }
  GraphEdge tight;
  tight.from = 0;
  tight.to = 1;
  tight.measurement = Pose2(1.0, 0.0, 0.0);
  tight.information = Eigen::Matrix3d::Identity() * 100.0;
  GraphEdge plain = tight;
  plain.from = 1;
  plain.to = 2;
  ASSERT_TRUE(graph.AddEdge(tight).ok());
  ASSERT_TRUE(graph.AddEdge(plain).ok());
  EXPECT_FALSE(WithGatingInformation(graph).has_value());  // nothing differs: no copy

  graph.mutable_edges()[0].gating_information = Eigen::Matrix3d::Identity();
  const auto gating = WithGatingInformation(graph);
  ASSERT_TRUE(gating.has_value());
  EXPECT_EQ(gating->edges()[0].information, Eigen::Matrix3d::Identity());
  EXPECT_EQ(gating->edges()[1].information, plain.information);
  EXPECT_EQ(graph.edges()[0].information, tight.information);  // the graph is untouched
  // A non-finite gating information is refused like a non-finite information.
  GraphEdge bad = plain;
  bad.gating_information = Eigen::Matrix3d::Constant(std::nan(""));
  EXPECT_FALSE(graph.AddEdge(bad).ok());
}

}  // namespace
}  // namespace longterm_mapper2d
