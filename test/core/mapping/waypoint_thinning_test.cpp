#include "longterm_mapper2d/core/mapping/waypoint_thinning.h"

#include <gtest/gtest.h>

#include <cmath>

namespace longterm_mapper2d {
namespace {

constexpr double kDistanceM = 0.5;
constexpr double kAngleRad = 0.785;

// A waypoint whose scan stamp names it, so a test can tell which ones survived.
Waypoint At(double x, double y, double theta, int session, double name) {
  Waypoint w;
  w.node_T_base = Pose2(x, y, theta);
  w.session_id = session;
  w.scan.stamp_s = name;
  w.scan.ranges = {1.0f, 2.0f};
  return w;
}

LocalMapNode Node(NodeId id, const Pose2& map_T_node, std::vector<Waypoint> waypoints) {
  LocalMapNode node;
  node.id = id;
  node.map_T_node = map_T_node;
  node.waypoints = std::move(waypoints);
  return node;
}

std::vector<double> Names(const LocalMapNode& node) {
  std::vector<double> names;
  for (const Waypoint& w : node.waypoints) names.push_back(w.scan.stamp_s);
  return names;
}

TEST(WaypointThinning, ANewerSessionOnAnotherNodeReplacesAnOlderView) {
  std::map<NodeId, LocalMapNode> nodes;
  nodes.emplace(1, Node(1, Pose2(), {At(1.0, 0.0, 0.0, 0, 1), At(3.0, 0.0, 0.0, 0, 2)}));
  // Node 2 sits 1 m to the left; its waypoint is at (1.3, 0.1) in the map, 0.2 rad turned.
  nodes.emplace(2, Node(2, Pose2(1.0, 0.0, 0.0), {At(0.3, 0.1, 0.2, 1, 3)}));
  EXPECT_EQ(DropWaypointsSeenAgain(&nodes, kDistanceM, kAngleRad), 1);
  EXPECT_EQ(Names(nodes.at(1)), std::vector<double>({2}));
  EXPECT_EQ(Names(nodes.at(2)), std::vector<double>({3}));
}

TEST(WaypointThinning, TheSameSessionAndOtherHeadingsAreKept) {
  std::map<NodeId, LocalMapNode> nodes;
  nodes.emplace(1, Node(1, Pose2(), {At(1.0, 0.0, 0.0, 1, 1), At(5.0, 0.0, 0.0, 0, 2)}));
  nodes.emplace(2, Node(2, Pose2(),
                        {At(1.1, 0.0, 0.0, 1, 3),     // same session as 1
                         At(5.0, 0.0, M_PI, 1, 4),    // the other way along
                         At(5.0, 0.6, 0.0, 1, 5)}));  // 0.6 m away
  EXPECT_EQ(DropWaypointsSeenAgain(&nodes, kDistanceM, kAngleRad), 0);
  EXPECT_EQ(nodes.at(1).waypoints.size(), 2u);
  EXPECT_EQ(nodes.at(2).waypoints.size(), 3u);
}

TEST(WaypointThinning, NodePosesPlaceTheWaypoints) {
  std::map<NodeId, LocalMapNode> nodes;
  // The same node-frame waypoint on nodes turned by 90 degrees: 1.4 m apart in the map.
  nodes.emplace(1, Node(1, Pose2(0.0, 0.0, 0.0), {At(1.0, 0.0, 0.0, 0, 1)}));
  nodes.emplace(2, Node(2, Pose2(0.0, 0.0, M_PI / 2), {At(1.0, 0.0, -M_PI / 2, 1, 2)}));
  EXPECT_EQ(DropWaypointsSeenAgain(&nodes, kDistanceM, kAngleRad), 0);
  // Turned back, they coincide.
  nodes.at(2).map_T_node = Pose2(0.0, 0.0, 0.0);
  nodes.at(2).waypoints[0].node_T_base = Pose2(1.2, 0.0, 0.0);
  EXPECT_EQ(DropWaypointsSeenAgain(&nodes, kDistanceM, kAngleRad), 1);
  EXPECT_TRUE(nodes.at(1).waypoints.empty());
}

TEST(WaypointThinning, OnlyKeptWaypointsCoverOlderOnes) {
  // Session 2 covers session 1's view, which would cover session 0's; session 0's is 0.8 m from
  // session 2's, so it stays: dropping it for a view that is itself gone would leave a gap.
  std::map<NodeId, LocalMapNode> nodes;
  nodes.emplace(1, Node(1, Pose2(), {At(0.8, 0.0, 0.0, 0, 1)}));
  nodes.emplace(2, Node(2, Pose2(), {At(0.4, 0.0, 0.0, 1, 2)}));
  nodes.emplace(3, Node(3, Pose2(), {At(0.0, 0.0, 0.0, 2, 3)}));
  EXPECT_EQ(DropWaypointsSeenAgain(&nodes, kDistanceM, kAngleRad), 1);
  EXPECT_EQ(Names(nodes.at(1)), std::vector<double>({1}));
  EXPECT_TRUE(nodes.at(2).waypoints.empty());
  EXPECT_EQ(Names(nodes.at(3)), std::vector<double>({3}));
  // Dropping again changes nothing.
  EXPECT_EQ(DropWaypointsSeenAgain(&nodes, kDistanceM, kAngleRad), 0);
}

TEST(WaypointThinning, SurvivorsKeepTheirOrderAcrossCellBorders) {
  std::map<NodeId, LocalMapNode> nodes;
  // Old views on both sides of cell borders (x = 0, x = -0.5) and a new one near each border.
  nodes.emplace(1, Node(1, Pose2(),
                        {At(-0.05, 0.0, 0.0, 0, 1), At(2.0, 2.0, 0.0, 0, 2),
                         At(-0.55, 0.0, 0.0, 0, 3), At(4.0, 0.0, 0.0, 0, 4)}));
  nodes.emplace(2, Node(2, Pose2(), {At(0.05, 0.0, 0.0, 1, 5), At(-0.49, 0.02, 0.0, 1, 6)}));
  EXPECT_EQ(DropWaypointsSeenAgain(&nodes, kDistanceM, kAngleRad), 2);
  EXPECT_EQ(Names(nodes.at(1)), std::vector<double>({2, 4}));
}

}  // namespace
}  // namespace longterm_mapper2d
