#include "longterm_mapper2d/core/mapping/trajectory_refiner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "testing/synthetic_scans.h"

namespace longterm_mapper2d {
namespace {

using test_support::CastScan;
using test_support::CloudSeenFrom;
using test_support::SyntheticLaser;

// A map of two local maps of `walls`, seen from two places, each node at its own pose with its
// cloud in its frame, as a finished session has them.
std::map<NodeId, LocalMapNode> TwoNodeMap(const std::vector<Segment>& walls, const Pose2& first,
                                          const Pose2& second) {
  std::map<NodeId, LocalMapNode> nodes;
  for (const auto& [id, map_T_node] : {std::make_pair(NodeId{3}, first), {NodeId{7}, second}}) {
    LocalMapNode& node = nodes[id];
    node.id = id;
    node.map_T_node = map_T_node;
    node.cloud = CloudSeenFrom(walls, map_T_node, 20.0);  // in the laser's (node's) frame
  }
  return nodes;
}

// A 270 deg laser, 1 cm range noise, mounted 0.1 m ahead of the base.
struct Scan {
  LaserScan scan;
  Pose2 base_T_laser = Pose2(0.1, 0.0, 0.0);
  Scan(const std::vector<Segment>& walls, const Pose2& map_T_base) {
    SyntheticLaser laser;
    laser.beams = 541;
    laser.fov_rad = 1.5 * M_PI;
    laser.range_noise_m = 0.01;
    scan = CastScan(walls, {}, map_T_base * base_T_laser, laser, 5);
  }
};

TEST(TrajectoryRefiner, AScanOffTheMapIsPutBackWhereItWasTaken) {
  const auto walls = test_support::IrregularRoom();
  const auto nodes = TwoNodeMap(walls, Pose2(-2.0, 0.5, 0.3), Pose2(2.0, -0.5, -1.0));
  const TrajectoryRefiner refiner({}, {}, {}, nodes);
  EXPECT_GT(refiner.map_points(), 200u);
  const Pose2 truth(0.5, 0.8, 0.7);
  const Scan scan(walls, truth);
  // The trajectory has it 6 cm and 1.7 deg off, as an early merge can leave a stretch.
  const Pose2 guess = truth * Pose2(0.05, -0.03, 0.03);
  const auto refined = refiner.Align(scan.scan, scan.base_T_laser, guess);
  ASSERT_TRUE(refined.has_value());
  EXPECT_LT((refined->translation() - truth.translation()).norm(), 0.01);
  EXPECT_LT(std::abs(NormalizeAngle(refined->theta() - truth.theta())), 0.003);
}

TEST(TrajectoryRefiner, InACorridorThePriorHoldsThePoseAlongIt) {
  // The map pins the scan across the corridor (y) and in heading, not along it (x): the error
  // across is removed, the one along stays about where the trajectory had it.
  const auto walls = test_support::Corridor();
  const auto nodes = TwoNodeMap(walls, Pose2(-3.0, 0.0, 0.0), Pose2(3.0, 0.2, 0.1));
  const TrajectoryRefiner refiner({}, {}, {}, nodes);
  const Pose2 truth(0.0, 0.3, 0.05);
  const Scan scan(walls, truth);
  const Pose2 guess(0.08, 0.36, 0.07);
  const auto refined = refiner.Align(scan.scan, scan.base_T_laser, guess);
  ASSERT_TRUE(refined.has_value());
  EXPECT_LT(std::abs(refined->y() - truth.y()), 0.01);
  EXPECT_LT(std::abs(NormalizeAngle(refined->theta() - truth.theta())), 0.003);
  EXPECT_NEAR(refined->x(), guess.x(), 0.02);
}

TEST(TrajectoryRefiner, PointsAMergeCarriedOverAreLeftOutOfTheTarget) {
  // Node 7 also holds the room as an older local map saw it, merged in while the graph had that
  // older node 6 cm and 1.1 deg off: those points are marked inherited, and the older node's scans,
  // re-anchored by the same merge, sit just as far off. Aligned with every point, such a scan
  // stays on the stale copy; with the own points only, it lands where it was taken.
  const auto walls = test_support::IrregularRoom();
  auto nodes = TwoNodeMap(walls, Pose2(-2.0, 0.5, 0.3), Pose2(2.0, -0.5, -1.0));
  nodes.erase(NodeId{3});  // the own points and the stale copy, one each
  LocalMapNode& node = nodes[NodeId{7}];
  const Pose2 stale(0.06, -0.03, 0.02);  // node 7's frame: where the merge put the old points
  for (RichPoint p : CloudSeenFrom(walls, node.map_T_node, 20.0)) {
    p = Transform(stale, p);
    p.inherited = true;
    node.cloud.push_back(p);
  }
  const Pose2 truth(0.5, 0.8, 0.7);
  const Scan scan(walls, truth);
  const Pose2 guess = node.map_T_node * stale * node.map_T_node.inverse() * truth;
  TrajectoryRefinementOptions options;
  const TrajectoryRefiner own(options, {}, {}, nodes);
  options.own_points_only = false;
  const TrajectoryRefiner all(options, {}, {}, nodes);
  EXPECT_LT(own.map_points(), all.map_points());
  const auto by_own = own.Align(scan.scan, scan.base_T_laser, guess);
  const auto by_all = all.Align(scan.scan, scan.base_T_laser, guess);
  ASSERT_TRUE(by_own.has_value());
  ASSERT_TRUE(by_all.has_value());
  EXPECT_LT((by_own->translation() - truth.translation()).norm(), 0.01);
  EXPECT_LT(std::abs(NormalizeAngle(by_own->theta() - truth.theta())), 0.003);
  EXPECT_GT((by_all->translation() - truth.translation()).norm(), 0.03);
}

TEST(TrajectoryRefiner, ACorrectionBeyondTheGatesIsRefused) {
  const auto walls = test_support::IrregularRoom();
  const auto nodes = TwoNodeMap(walls, Pose2(-2.0, 0.5, 0.3), Pose2(2.0, -0.5, -1.0));
  const Pose2 truth(0.5, 0.8, 0.7);
  const Scan scan(walls, truth);
  const Pose2 guess = truth * Pose2(0.05, -0.03, 0.0);
  TrajectoryRefinementOptions options;
  EXPECT_TRUE(TrajectoryRefiner(options, {}, {}, nodes).Align(scan.scan, scan.base_T_laser, guess));
  options.max_correction_m = 0.03;
  EXPECT_FALSE(
      TrajectoryRefiner(options, {}, {}, nodes).Align(scan.scan, scan.base_T_laser, guess));
  options = {};
  options.max_correction_rad = 0.01;
  EXPECT_FALSE(TrajectoryRefiner(options, {}, {}, nodes)
                   .Align(scan.scan, scan.base_T_laser, truth * Pose2(0.0, 0.0, 0.03)));
}

TEST(TrajectoryRefiner, AScanTheMapDoesNotCoverIsLeftAlone) {
  // Taken in another room (the map's walls do not see it): too few partners, no refinement; an
  // empty map too.
  const auto nodes =
      TwoNodeMap(test_support::IrregularRoom(), Pose2(-2.0, 0.5, 0.3), Pose2(2.0, -0.5, -1.0));
  const Pose2 elsewhere(60.0, 40.0, 0.0);
  const Scan scan(test_support::IrregularRoom(), Pose2());
  EXPECT_FALSE(TrajectoryRefiner({}, {}, {}, nodes).Align(scan.scan, scan.base_T_laser, elsewhere));
  EXPECT_FALSE(TrajectoryRefiner({}, {}, {}, {}).Align(scan.scan, scan.base_T_laser, Pose2()));
}

TEST(TrajectoryRefinementOptions, BadValuesAreNamed) {
  TrajectoryRefinementOptions options;
  options.max_correspondence_distance_m = 0.0;
  options.min_correspondence_ratio = 1.5;
  options.threads = 0;
  OptionErrors errors;
  options.Validate(errors);
  const std::string text = errors.ToString();
  EXPECT_NE(text.find("max_correspondence_distance_m"), std::string::npos);
  EXPECT_NE(text.find("min_correspondence_ratio"), std::string::npos);
  EXPECT_NE(text.find("threads"), std::string::npos);
}

}  // namespace
}  // namespace longterm_mapper2d
