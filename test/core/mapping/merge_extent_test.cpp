#include "longterm_mapper2d/core/mapping/merge_extent.h"

#include <gtest/gtest.h>

#include <cmath>

namespace longterm_mapper2d {
namespace {

LocalMapNode Node(NodeId id, const Pose2& map_T_node, const std::vector<Pose2>& node_T_waypoints) {
  LocalMapNode node;
  node.id = id;
  node.map_T_node = map_T_node;
  for (const Pose2& node_T_base : node_T_waypoints) {
    Waypoint w;
    w.node_T_base = node_T_base;
    node.waypoints.push_back(w);
  }
  return node;
}

TEST(MergeExtent, ReachIsTheFarthestWaypointSeenFromTheSurvivorsOrigin) {
  // The survivor at (1, 0) facing +y; the node at (1, 2) facing +x, its waypoint 1 m ahead of it:
  // in the survivor's frame the node sits at (2, 0) and the waypoint at (2, -1).
  const LocalMapNode survivor = Node(2, Pose2(1.0, 0.0, M_PI / 2), {});
  const LocalMapNode node = Node(1, Pose2(1.0, 2.0, 0.0), {Pose2(), Pose2(1.0, 0.0, 0.3)});
  EXPECT_NEAR(ReachFrom(survivor, node), std::sqrt(5.0), 1e-12);
  // Without waypoints, the node's origin.
  EXPECT_NEAR(ReachFrom(survivor, Node(1, Pose2(1.0, 2.0, 0.0), {})), 2.0, 1e-12);
}

TEST(MergeExtent, MembersReachingBeyondTheExtentStayNodes) {
  std::map<NodeId, LocalMapNode> nodes;
  // Near: origin 2 m away, waypoints within 1 m of it.
  nodes.emplace(1, Node(1, Pose2(2.0, 0.0, 0.0), {Pose2(), Pose2(1.0, 0.0, 0.0)}));
  // Origin 3 m away, but a merge once gave it a waypoint 6 m ahead of it: 9 m from the survivor.
  nodes.emplace(2, Node(2, Pose2(3.0, 0.0, 0.0), {Pose2(), Pose2(6.0, 0.0, 0.0)}));
  // Its origin alone is too far.
  nodes.emplace(3, Node(3, Pose2(0.0, -8.5, 0.0), {}));
  // The survivor, the newest; its own waypoints do not count.
  nodes.emplace(4, Node(4, Pose2(), {Pose2(20.0, 0.0, 0.0)}));
  EXPECT_EQ(MergeMembersWithinExtent(nodes, {1, 2, 3, 4}, 8.0), (std::vector<NodeId>{1, 4}));
  EXPECT_EQ(MergeMembersWithinExtent(nodes, {1, 2, 3, 4}, 9.5), (std::vector<NodeId>{1, 2, 3, 4}));
  // 0: no limit.
  EXPECT_EQ(MergeMembersWithinExtent(nodes, {1, 2, 3, 4}, 0.0), (std::vector<NodeId>{1, 2, 3, 4}));
  // A set left with the survivor alone merges nothing.
  EXPECT_EQ(MergeMembersWithinExtent(nodes, {3, 4}, 8.0), (std::vector<NodeId>{4}));
}

}  // namespace
}  // namespace longterm_mapper2d
