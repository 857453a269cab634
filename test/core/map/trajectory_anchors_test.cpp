#include "longterm_mapper2d/core/map/trajectory_anchors.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

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
  const std::vector<AnchoredPose> anchors = {
      {1.0, 2, node_T_base}, {2.0, 4, node_T_base}, {3.0, kMapFrame, Pose2(5.0, 6.0, 0.7)}};
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
  const auto poses = ReexpressTrajectory(TwoNodesAndARemovedOne(), {{1.0, 5, Pose2()}});
  ASSERT_FALSE(poses.ok());
  EXPECT_NE(poses.status().message().find("node 5"), std::string::npos);
}

TEST(TrajectoryAnchors, FilesRoundTripAndBadLinesAreRefused) {
  char dir_template[] = "/tmp/anchors_test_XXXXXX";
  const std::string dir = ::mkdtemp(dir_template);
  const std::vector<AnchoredPose> anchors = {{976052857.337, 12, Pose2(0.25, -1.5, 3.0)},
                                             {976052857.5, kMapFrame, Pose2(1.0, 2.0, -0.5)}};
  ASSERT_TRUE(WriteTrajectoryAnchors(dir + "/a.txt", anchors).ok());
  const auto read = ReadTrajectoryAnchors(dir + "/a.txt");
  ASSERT_TRUE(read.ok()) << read.status().message();
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ((*read)[0].node, 12);
  EXPECT_EQ((*read)[1].node, kMapFrame);
  EXPECT_NEAR((*read)[0].stamp_s, 976052857.337, 1e-6);
  EXPECT_NEAR((*read)[0].pose.y(), -1.5, 1e-6);
  for (const char* bad :
       {"1.0 3 0.1 0.2\n", "1.0 3 0.1 0.2 0.3 9\n", "1.0 -2 0 0 0\n", "1.0 x 0 0 0\n",
        "1.0 3 nan 0 0\n", "1.0 3.5 0 0 0\n", "1.0 1e300 0 0 0\n"}) {
    std::ofstream(dir + "/bad.txt") << "# header\n" << bad;
    const auto refused = ReadTrajectoryAnchors(dir + "/bad.txt");
    ASSERT_FALSE(refused.ok()) << bad;
    EXPECT_NE(refused.status().message().find("bad.txt:2"), std::string::npos) << bad;
  }
  EXPECT_FALSE(ReadTrajectoryAnchors(dir + "/missing.txt").ok());
  std::remove((dir + "/a.txt").c_str());
  std::remove((dir + "/bad.txt").c_str());
}

}  // namespace
}  // namespace longterm_mapper2d
