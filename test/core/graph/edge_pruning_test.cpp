#include "longterm_mapper2d/core/graph/edge_pruning.h"

#include <gtest/gtest.h>

namespace longterm_mapper2d {
namespace {

class EdgePruningTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (GraphNodeId id = 0; id < 5; ++id) {
      GraphNode node;
      node.id = id;
      node.pose = Pose2(static_cast<double>(id), 0.0, 0.0);
      ASSERT_TRUE(graph_.AddNode(node).ok());
    }
  }
  void Connect(GraphNodeId a, GraphNodeId b, double information,
               EdgeKind kind = EdgeKind::kCondensed) {
    GraphEdge edge;
    edge.from = a;
    edge.to = b;
    edge.measurement = graph_.node(a).pose.Between(graph_.node(b).pose);
    edge.information =
        Eigen::Vector3d(information, 2.0 * information, 10.0 * information).asDiagonal();
    edge.kind = kind;
    ASSERT_TRUE(graph_.AddEdge(edge).ok());
  }
  bool Has(GraphNodeId a, GraphNodeId b) const { return graph_.FindEdge(a, b).has_value(); }

  PoseGraph graph_;
};

TEST_F(EdgePruningTest, AUselessEdgeBesideStrongOnesGoes) {
  Connect(0, 1, 100.0, EdgeKind::kOdometry);
  Connect(1, 2, 100.0);
  Connect(0, 2, 1e-9);  // 1e-8 in its strongest direction, against 100 at both ends
  EXPECT_EQ(PruneNegligibleCondensedEdges(&graph_, 1e-6), 1);
  EXPECT_FALSE(Has(0, 2));
  EXPECT_TRUE(Has(0, 1));
  EXPECT_TRUE(Has(1, 2));
}

TEST_F(EdgePruningTest, TheRatioIsAgainstTheWeakestDirectionOfTheBestOtherEdge) {
  Connect(0, 1, 100.0, EdgeKind::kOdometry);  // weakest direction 100
  Connect(1, 2, 100.0);
  Connect(0, 2, 2e-5);  // strongest direction 2e-4 > 1e-6 x 100
  EXPECT_EQ(PruneNegligibleCondensedEdges(&graph_, 1e-6), 0);
  graph_.mutable_edges().back().information *= 0.25;  // 5e-5 < 1e-4
  EXPECT_EQ(PruneNegligibleCondensedEdges(&graph_, 1e-6), 1);
}

TEST_F(EdgePruningTest, TheOnlyTieOfANodeStays) {
  Connect(0, 1, 100.0);
  Connect(1, 2, 100.0);
  Connect(2, 3, 1e-12);  // node 3 has nothing else
  EXPECT_EQ(PruneNegligibleCondensedEdges(&graph_, 1e-6), 0);
  EXPECT_TRUE(Has(2, 3));
}

TEST_F(EdgePruningTest, OfTwoUselessEdgesInACycleOneStays) {
  // 3 hangs off the graph by two useless edges: one of them (the weaker) goes, the other keeps
  // 3 connected.
  Connect(0, 1, 100.0);
  Connect(1, 2, 100.0);
  Connect(1, 3, 1e-11);
  Connect(2, 3, 1e-12);
  Connect(3, 4, 100.0);
  EXPECT_EQ(PruneNegligibleCondensedEdges(&graph_, 1e-6), 1);
  EXPECT_TRUE(Has(1, 3));
  EXPECT_FALSE(Has(2, 3));
}

TEST_F(EdgePruningTest, OnlyCondensedEdgesNegligibleAtBothEndsGo) {
  Connect(0, 1, 100.0);
  Connect(1, 2, 100.0);
  Connect(0, 2, 1e-9, EdgeKind::kOdometry);  // measured edges are never pruned
  Connect(2, 3, 1e-9);                       // 3's other tie is as weak: not negligible there
  Connect(3, 4, 2e-9);
  Connect(4, 0, 1e-5);  // 0's best other edge is 100, but 4's is 2e-9
  EXPECT_EQ(PruneNegligibleCondensedEdges(&graph_, 1e-6), 0);
  EXPECT_EQ(graph_.edges().size(), 6u);
  // A ratio of zero turns pruning off.
  Connect(1, 3, 1e-12);
  EXPECT_EQ(PruneNegligibleCondensedEdges(&graph_, 0.0), 0);
  EXPECT_EQ(PruneNegligibleCondensedEdges(&graph_, 1e-6), 0);  // 1-3 at 3: 3's best is 2e-9
}

}  // namespace
}  // namespace longterm_mapper2d
