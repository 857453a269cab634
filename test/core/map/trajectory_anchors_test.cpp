#include "longterm_mapper2d/core/map/trajectory_anchors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "testing/temp_dir.h"

namespace longterm_mapper2d {
namespace {

SessionMap TwoNodesAndARemovedOne() {
  SessionMap map;
  for (NodeId id : {2, 9}) {
    LocalMapNode node;
    node.id = id;
    node.map_T_node = Pose2(id, 1.0, 0.5 * id);
    map.nodes.emplace(id, node);
  }
  map.removed_nodes[4] = RemovedNode{9, Pose2(-1.0, 0.5, 0.3)};
  return map;
}

TEST(TrajectoryAnchors, PosesFollowTheirNodeOrTheNodeThatTookItOver) {
  const SessionMap map = TwoNodesAndARemovedOne();
  const Pose2 node_T_base(0.4, -0.2, 0.1);
  const std::vector<AnchoredPose> anchors = {{1.0, 2, node_T_base, std::nullopt},
                                             {2.0, 4, node_T_base, std::nullopt},
                                             {3.0, kMapFrame, Pose2(5.0, 6.0, 0.7), std::nullopt}};
  const auto poses = ReexpressTrajectory(map, anchors);
  ASSERT_TRUE(poses.ok()) << poses.status().message();
  ASSERT_EQ(poses->size(), 3u);
  auto near = [](const Pose2& a, const Pose2& b) {
    return (a.translation() - b.translation()).norm() < 1e-12 &&
           std::abs(NormalizeAngle(a.theta() - b.theta())) < 1e-12;
  };
  EXPECT_TRUE(near((*poses)[0].pose, map.nodes.at(2).map_T_node * node_T_base));
  EXPECT_TRUE(near((*poses)[1].pose, map.nodes.at(9).map_T_node *
                                         map.removed_nodes.at(4).survivor_T_removed * node_T_base));
  EXPECT_TRUE(near((*poses)[2].pose, Pose2(5.0, 6.0, 0.7)));
  EXPECT_EQ((*poses)[1].stamp_s, 2.0);
}

TEST(TrajectoryAnchors, ANodeTheMapNeverHadIsAnError) {
  const auto poses =
      ReexpressTrajectory(TwoNodesAndARemovedOne(), {{1.0, 5, Pose2(), std::nullopt}});
  ASSERT_FALSE(poses.ok());
  EXPECT_NE(poses.status().message().find("node 5"), std::string::npos);
}

// Ten scans 1 s apart along a straight line, the first five on node 2, the last five on node 9,
// as the session wrote them. A later map moved node 9 by 0.2 m sideways (relative to node 2).
TEST(TrajectoryAnchors, SmoothingTakesTheJumpOutOfAStretchTwoNodesCarry) {
  SessionMap map;
  for (NodeId id : {2, 9}) {
    LocalMapNode node;
    node.id = id;
    node.map_T_node = Pose2(id == 2 ? 0.0 : 5.0, 0.0, 0.0);
    map.nodes.emplace(id, node);
  }
  std::vector<AnchoredPose> anchors;
  for (int i = 0; i < 10; ++i) {
    const Pose2 written(i, 0.0, 0.0);
    const NodeId node = i < 5 ? 2 : 9;
    anchors.push_back(
        {static_cast<double>(i), node, map.nodes.at(node).map_T_node.inverse() * written, written});
  }
  // In the map that wrote them: the written poses, smoothed or not.
  for (double window_s : {0.0, 8.0}) {
    const auto same = ReexpressTrajectory(map, anchors, window_s);
    ASSERT_TRUE(same.ok());
    for (int i = 0; i < 10; ++i) {
      EXPECT_LT(((*same)[i].pose.translation() - anchors[i].written->translation()).norm(), 1e-9);
    }
  }
  map.nodes.at(9).map_T_node = Pose2(5.0, 0.2, 0.0);
  auto largest_step_across_m = [&](double window_s) {
    const auto poses = ReexpressTrajectory(map, anchors, window_s);
    EXPECT_TRUE(poses.ok());
    double largest = 0.0;
    for (int i = 1; i < 10; ++i) {
      largest = std::max(largest, std::abs((*poses)[i].pose.y() - (*poses)[i - 1].pose.y()));
    }
    return largest;
  };
  EXPECT_NEAR(largest_step_across_m(0.0), 0.2, 1e-9);
  // Within 8 s every scan sees both nodes' corrections: the jump is spread over the stretch.
  EXPECT_LT(largest_step_across_m(8.0), 0.05);
  // Without the written poses there is no chain to smooth along: unchanged.
  for (AnchoredPose& anchor : anchors) anchor.written.reset();
  EXPECT_NEAR(largest_step_across_m(8.0), 0.2, 1e-9);
}

TEST(TrajectoryAnchors, FilesRoundTripAndBadLinesAreRefused) {
  const test_support::ScopedTempDir temp("anchors_test");
  const std::string& dir = temp.path();
  const std::vector<AnchoredPose> anchors = {
      {976052857.337, 12, Pose2(0.25, -1.5, 3.0), Pose2(7.0, 8.0, -1.0)},
      {976052857.5, kMapFrame, Pose2(1.0, 2.0, -0.5), std::nullopt}};
  ASSERT_TRUE(WriteTrajectoryAnchors(dir + "/a.txt", anchors).ok());
  const auto read = ReadTrajectoryAnchors(dir + "/a.txt");
  ASSERT_TRUE(read.ok()) << read.status().message();
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ((*read)[0].node, 12);
  EXPECT_EQ((*read)[1].node, kMapFrame);
  EXPECT_NEAR((*read)[0].stamp_s, 976052857.337, 1e-6);
  EXPECT_NEAR((*read)[0].pose.y(), -1.5, 1e-6);
  ASSERT_TRUE((*read)[0].written.has_value());
  EXPECT_NEAR((*read)[0].written->theta(), -1.0, 1e-6);
  EXPECT_FALSE((*read)[1].written.has_value());
  for (const char* bad :
       {"1.0 3 0.1 0.2\n", "1.0 3 0.1 0.2 0.3 9\n", "1.0 3 0 0 0 1 2\n", "1.0 -2 0 0 0\n",
        "1.0 x 0 0 0\n", "1.0 3 nan 0 0\n", "1.0 3.5 0 0 0\n", "1.0 1e300 0 0 0\n"}) {
    std::ofstream(dir + "/bad.txt") << "# header\n" << bad;
    const auto refused = ReadTrajectoryAnchors(dir + "/bad.txt");
    ASSERT_FALSE(refused.ok()) << bad;
    EXPECT_NE(refused.status().message().find("bad.txt:2"), std::string::npos) << bad;
  }
  EXPECT_FALSE(ReadTrajectoryAnchors(dir + "/missing.txt").ok());
}

}  // namespace
}  // namespace longterm_mapper2d
