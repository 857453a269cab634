#include "longterm_mapper2d/core/graph/frame_anchor.h"

#include <gtest/gtest.h>

#include <cmath>

namespace longterm_mapper2d {
namespace {

// Seven nodes around a floor, with the anchors where a loaded map had them.
class FrameAnchorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (GraphNodeId id = 0; id < 7; ++id) {
      const Pose2 anchor(3.0 * std::cos(id), 2.0 * id - 4.0, 0.4 * id - 1.0);
      anchors_[id] = anchor;
      GraphNode node;
      node.id = id;
      node.pose = anchor;
      ASSERT_TRUE(graph_.AddNode(node).ok());
    }
  }
  // Every node moved by `motion` (map' <- map).
  void MoveAll(const Pose2& motion) {
    for (GraphNodeId id = 0; id < 7; ++id) {
      graph_.mutable_node(id).pose = motion * graph_.node(id).pose;
    }
  }
  double Distance(GraphNodeId id) const {
    return (graph_.node(id).pose.vector() - anchors_.at(id).vector()).norm();
  }

  PoseGraph graph_;
  std::map<GraphNodeId, Pose2> anchors_;
};

TEST_F(FrameAnchorTest, ARigidMotionOfTheWholeGraphIsUndone) {
  const Pose2 motion(1.5, -0.7, 0.3);
  MoveAll(motion);
  const auto correction = FrameCorrection(graph_, anchors_);
  ASSERT_TRUE(correction.has_value());
  EXPECT_LT((correction->vector() - motion.inverse().vector()).norm(), 1e-12);
  MoveFrame(graph_, *correction);
  for (GraphNodeId id = 0; id < 7; ++id) EXPECT_LT(Distance(id), 1e-12) << "node " << id;
}

TEST_F(FrameAnchorTest, MovingTheFrameKeepsEveryRelativePose) {
  const Pose2 before = graph_.node(2).pose.Between(graph_.node(5).pose);
  MoveFrame(graph_, Pose2(4.0, 1.0, -2.0));
  const Pose2 after = graph_.node(2).pose.Between(graph_.node(5).pose);
  EXPECT_LT((before.vector() - after.vector()).norm(), 1e-12);
  EXPECT_GT(Distance(0), 1.0);
}

TEST_F(FrameAnchorTest, AFewNodesTurnedFarOffDoNotDragTheFrame) {
  // The bulk moved by a small motion; two weakly tied nodes turned by -24 degrees besides (the
  // hour-6 case). The mean of the heading offsets would put the bulk 0.1 rad off.
  MoveAll(Pose2(0.2, 0.1, 0.02));
  for (GraphNodeId id : {1, 4}) {
    graph_.mutable_node(id).pose = Pose2(0.0, 0.0, -0.42) * graph_.node(id).pose;
  }
  double mean_offset = 0.0;
  for (const auto& [id, anchor] : anchors_) {
    mean_offset += NormalizeAngle(anchor.theta() - graph_.node(id).pose.theta()) / 7.0;
  }
  ASSERT_GT(std::abs(mean_offset + 0.02), 0.1);
  const auto correction = FrameCorrection(graph_, anchors_);
  ASSERT_TRUE(correction.has_value());
  MoveFrame(graph_, *correction);
  for (GraphNodeId id : {0, 2, 3, 5, 6}) EXPECT_LT(Distance(id), 1e-9) << "node " << id;
  for (GraphNodeId id : {1, 4}) EXPECT_GT(Distance(id), 0.4) << "node " << id;
}

TEST_F(FrameAnchorTest, HeadingOffsetsAroundPiHaveNoSeam) {
  // Offsets of +-(pi - 0.01) are 0.02 apart, not 2 pi: the frame turns by about pi.
  for (GraphNodeId id = 0; id < 7; ++id) {
    const double turn = id % 2 == 0 ? M_PI - 0.01 : -(M_PI - 0.01);
    graph_.mutable_node(id).pose = Pose2(0.0, 0.0, turn) * anchors_.at(id);
  }
  const auto correction = FrameCorrection(graph_, anchors_);
  ASSERT_TRUE(correction.has_value());
  EXPECT_GT(std::abs(correction->theta()), M_PI - 0.02);
}

TEST_F(FrameAnchorTest, OnlyAnchorsOfNodesInTheGraphCount) {
  EXPECT_FALSE(FrameCorrection(graph_, {{42, Pose2(1.0, 2.0, 3.0)}}).has_value());
  EXPECT_FALSE(FrameCorrection(graph_, {}).has_value());
  // One anchored node in the graph decides alone; the anchor of a missing node changes nothing.
  MoveAll(Pose2(0.0, 0.0, 0.5));
  const auto correction = FrameCorrection(graph_, {{3, anchors_.at(3)}, {42, Pose2(9, 9, 1)}});
  ASSERT_TRUE(correction.has_value());
  MoveFrame(graph_, *correction);
  EXPECT_LT(Distance(3), 1e-12);
  EXPECT_LT(Distance(6), 1e-9);
}

}  // namespace
}  // namespace longterm_mapper2d
