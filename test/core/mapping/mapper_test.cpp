#include "longterm_mapper2d/core/mapping/mapper.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cstdio>
#include <random>

#include "testing/synthetic_scans.h"

namespace longterm_mapper2d {
namespace {

using test_support::CastScan;
using test_support::SyntheticLaser;

// A robot driving a loop through a long irregular corridor world with noisy odometry.
struct Drive {
  std::vector<ScanInput> inputs;
  std::vector<Pose2> truth;
};

std::vector<Segment> LongWorld() {
  // Two rooms joined by a corridor with doorways and clutter, 24 m long.
  auto seg = [](double x1, double y1, double x2, double y2) {
    return Segment{Eigen::Vector2d(x1, y1), Eigen::Vector2d(x2, y2)};
  };
  std::vector<Segment> s = {seg(-2, -2, 22, -2), seg(22, -2, 22, 3), seg(22, 3, -2, 3),
                            seg(-2, 3, -2, -2)};
  for (double x = 1.0; x < 21.0; x += 2.7) {
    const auto box = BoxSegments(x, -1.8 + 0.3 * std::sin(x), x + 0.4, -1.2 + 0.3 * std::sin(x));
    s.insert(s.end(), box.begin(), box.end());
    s.push_back(seg(x + 1.0, 3.0, x + 1.3, 2.2 + 0.2 * std::cos(x)));
  }
  return s;
}

Drive MakeDrive(int steps, double step_m, std::uint64_t seed, double slip = 0.03,
                double drift_rad_per_m = 0.01, double heading_noise_rad = 0.005) {
  Drive drive;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const auto world = LongWorld();
  SyntheticLaser laser;
  laser.beams = 270;
  laser.fov_rad = 1.5 * M_PI;
  laser.range_noise_m = 0.01;
  Pose2 truth(0.0, 0.5, 0.0), odom = truth;
  for (int i = 0; i < steps; ++i) {
    const Pose2 step(step_m, 0.0, 0.02 * std::cos(0.1 * i));  // heading stays within 0.2 rad
    if (i > 0) {
      truth = truth * step;
      odom =
          odom * Pose2(step.x() * (1.0 + slip * unit(rng)), 0.0,
                       step.theta() + drift_rad_per_m * step.x() + heading_noise_rad * unit(rng));
    }
    ScanInput input;
    input.scan = CastScan(world, {}, truth, laser, seed * 1000 + i);
    input.scan.stamp_s = 0.1 * i;
    input.odom_T_base = odom;
    drive.inputs.push_back(input);
    drive.truth.push_back(truth);
  }
  return drive;
}

double FinalError(const std::vector<StampedPose2>& trajectory, const Drive& drive) {
  return (trajectory.back().pose.translation() - drive.truth.back().translation()).norm();
}

TEST(Mapper, ScanMatchingBeatsNoisyOdometry) {
  const Drive drive = MakeDrive(150, 0.12, 3);
  Mapper mapper(MapperOptions{});
  for (const auto& input : drive.inputs) mapper.AddScan(input);
  mapper.Finish();
  MapperOptions dead_reckoning;
  dead_reckoning.tracker.scan_matching = false;
  Mapper odometry(dead_reckoning);
  for (const auto& input : drive.inputs) odometry.AddScan(input);
  odometry.Finish();
  const auto tracked = mapper.Trajectory();
  ASSERT_EQ(tracked.size(), drive.inputs.size());
  const double tracked_error = FinalError(tracked, drive);
  const double odometry_error = FinalError(odometry.Trajectory(), drive);
  EXPECT_LT(tracked_error, 0.1);
  EXPECT_LT(tracked_error, 0.3 * odometry_error) << tracked_error << " vs " << odometry_error;
  EXPECT_EQ(mapper.stats().counters.count("tracker_failures"), 0u);
}

TEST(Mapper, CreatesANodeEveryStretchWithWaypointsAndEdges) {
  const Drive drive = MakeDrive(150, 0.12, 4);  // 18 m
  Mapper mapper(MapperOptions{});
  for (const auto& input : drive.inputs) mapper.AddScan(input);
  mapper.Finish();
  // 18 m in 2.5 m stretches: the first node (at the start, holding the first stretch), 6 full
  // stretches and the last partial one.
  EXPECT_GE(mapper.nodes().size(), 8u);
  EXPECT_LE(mapper.nodes().size(), 9u);
  EXPECT_EQ(mapper.edges().size(), mapper.nodes().size() - 1);
  // The first node stands where the drive started (its first waypoint) and holds the first
  // stretch (21 scans); the written trajectory, refined against the finished map, starts within
  // millimetres of it.
  const LocalMapNode& first = mapper.nodes().begin()->second;
  ASSERT_FALSE(first.waypoints.empty());
  EXPECT_LT(first.waypoints.front().node_T_base.translation().norm(), 1e-9);
  EXPECT_LT(
      (first.map_T_node.translation() - mapper.Trajectory().front().pose.translation()).norm(),
      0.01);
  EXPECT_GE(first.waypoints.size(), 20u);
  std::size_t waypoints = 0;
  for (const auto& [id, node] : mapper.nodes()) {
    waypoints += node.waypoints.size();
    EXPECT_FALSE(node.cloud.empty());
  }
  // One waypoint per 0.1 m of travel at most (every processed scan here moved 0.12 m).
  EXPECT_EQ(waypoints, drive.inputs.size());
  for (std::size_t i = 0; i < mapper.edges().size(); ++i) {
    const OdometryEdge& edge = mapper.edges()[i];
    EXPECT_EQ(edge.to, edge.from + 1);
    // Every stretch is 2.5 m (to the next scan), except the last one that Finish() closes; the
    // first edge runs from the start over two.
    if (i + 1 < mapper.edges().size()) {
      EXPECT_LT(std::abs(edge.from_T_to.translation().norm() - (i == 0 ? 5.0 : 2.5)), 0.15);
    }
    EXPECT_TRUE(edge.information.allFinite());
    EXPECT_GT(edge.information.determinant(), 0.0);
  }
  EXPECT_EQ(mapper.WaypointScans().size(), waypoints);
}

TEST(Mapper, SkipsScansWhileOdometryStandsStillButGivesThemPoses) {
  Drive drive = MakeDrive(20, 0.12, 5);
  // Repeat each scan with the same odometry: the copies are skipped.
  std::vector<ScanInput> inputs;
  for (auto input : drive.inputs) {
    inputs.push_back(input);
    input.scan.stamp_s += 0.05;
    inputs.push_back(input);
  }
  Mapper mapper(MapperOptions{});
  for (const auto& input : inputs) mapper.AddScan(input);
  mapper.Finish();
  EXPECT_EQ(mapper.stats().scans_processed, 20u);
  EXPECT_EQ(mapper.stats().scans_skipped.at("no_motion"), 20u);
  const auto trajectory = mapper.Trajectory();
  ASSERT_EQ(trajectory.size(), 40u);
  // Each copy is dead reckoned (no motion: the original's pose) or located against the local map
  // its original went into: the same place, within what fusing the original into the map moved
  // its points (measured: at most 0.8 mm).
  for (std::size_t i = 0; i + 1 < trajectory.size(); i += 2) {
    EXPECT_LT((trajectory[i].pose.translation() - trajectory[i + 1].pose.translation()).norm(),
              0.002);
  }
  // Located, or dead reckoned once registration shows odometry good enough (3 % slip here).
  const auto& counters = mapper.stats().counters;
  auto count = [&](const char* key) { return counters.count(key) ? counters.at(key) : 0u; };
  EXPECT_EQ(count("skipped_scans_located") + count("skipped_scans_dead_reckoned"), 20u);
}

// Error of the step between consecutive trajectory poses against the truth's, averaged (m + rad).
double MeanStepError(const std::vector<StampedPose2>& trajectory, const std::vector<Pose2>& truth) {
  double sum = 0.0;
  for (std::size_t i = 1; i < trajectory.size(); ++i) {
    const Pose2 error = truth[i - 1].Between(truth[i]).inverse() *
                        trajectory[i - 1].pose.Between(trajectory[i].pose);
    sum += error.translation().norm() + std::abs(NormalizeAngle(error.theta()));
  }
  return sum / (trajectory.size() - 1);
}

TEST(Mapper, ScansBetweenProcessedOnesAreLocatedAgainstTheLocalMap) {
  // 4 cm per scan: two of every three scans move too little to be processed. Odometry slips 20 %
  // and drifts 0.1 rad per metre, so dead reckoning from the last processed scan is visibly off.
  const Drive drive = MakeDrive(240, 0.04, 6, 0.2, 0.1);
  double step_error[2];
  for (const bool locate : {false, true}) {
    MapperOptions options;
    options.tracker.locate_skipped_scans = locate;
    Mapper mapper(options);
    for (const auto& input : drive.inputs) mapper.AddScan(input);
    mapper.Finish();
    const auto skipped = mapper.stats().scans_skipped.at("no_motion");
    EXPECT_GT(skipped, 120u);
    const auto& counters = mapper.stats().counters;
    if (locate) {
      EXPECT_EQ(counters.at("skipped_scans_located"), skipped);
    } else {
      EXPECT_EQ(counters.count("skipped_scans_located"), 0u);
    }
    const auto trajectory = mapper.Trajectory();
    ASSERT_EQ(trajectory.size(), drive.truth.size());
    step_error[locate] = MeanStepError(trajectory, drive.truth);
  }
  // Measured: mean step error (m + rad) 0.0028 located, 0.0140 dead reckoned.
  std::printf("mean step error: located %.4f, dead reckoned %.4f\n", step_error[1], step_error[0]);
  EXPECT_LT(step_error[1], 0.5 * step_error[0]) << step_error[1] << " vs " << step_error[0];
}

TEST(Mapper, WithGoodOdometryTheScansInBetweenAreDeadReckoned) {
  // Perfect odometry: registration moves its guess by the registration's own noise only (under
  // 5 mm and 5 mrad), so once that shows, the scans in between are dead reckoned, not located.
  const Drive drive = MakeDrive(240, 0.04, 7, 0.0, 0.0, 0.0);
  Mapper mapper(MapperOptions{});
  for (const auto& input : drive.inputs) mapper.AddScan(input);
  mapper.Finish();
  const auto& counters = mapper.stats().counters;
  const auto skipped = mapper.stats().scans_skipped.at("no_motion");
  ASSERT_TRUE(counters.count("skipped_scans_dead_reckoned"));
  EXPECT_GT(counters.at("skipped_scans_dead_reckoned"), skipped / 2);
  // The first ones are located: the average starts high.
  EXPECT_GT(counters.at("skipped_scans_located"), 0u);
}

TEST(Mapper, ScansWithDuplicateStampsAreSkippedAndChangeNothing) {
  // A driver glitch publishes every scan twice with the same stamp: the copy has no motion since
  // the original, so it is skipped, gets the original's pose, and the map is the same as without.
  Drive drive = MakeDrive(20, 0.12, 9);
  Mapper once(MapperOptions{}), twice(MapperOptions{});
  for (const auto& input : drive.inputs) {
    once.AddScan(input);
    twice.AddScan(input);
    twice.AddScan(input);
  }
  once.Finish();
  twice.Finish();
  EXPECT_EQ(twice.stats().scans_processed, once.stats().scans_processed);
  EXPECT_EQ(twice.stats().scans_skipped.at("no_motion"), 20u);
  EXPECT_EQ(twice.nodes().size(), once.nodes().size());
  const auto a = once.Trajectory(), b = twice.Trajectory();
  ASSERT_EQ(b.size(), 2 * a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(b[2 * i].stamp_s, a[i].stamp_s);
    EXPECT_EQ(b[2 * i + 1].stamp_s, a[i].stamp_s);
    EXPECT_LT((b[2 * i].pose.translation() - a[i].pose.translation()).norm(), 1e-9);
    EXPECT_LT((b[2 * i + 1].pose.translation() - a[i].pose.translation()).norm(), 1e-9);
  }
}

TEST(Mapper, ATrackerFailureResetsTheLocalMapAndStartsANode) {
  Drive drive = MakeDrive(40, 0.12, 6);
  // Scan 25 sees a different world (a kidnap of the laser's view): registration must reject it.
  SyntheticLaser laser;
  laser.beams = 270;
  laser.fov_rad = 1.5 * M_PI;
  drive.inputs[25].scan =
      CastScan(test_support::IrregularRoom(), {}, Pose2(0.5, 0.3, 2.0), laser, 99);
  drive.inputs[25].scan.stamp_s = 2.5;
  Mapper mapper(MapperOptions{});
  for (const auto& input : drive.inputs) mapper.AddScan(input);
  mapper.Finish();
  ASSERT_GE(mapper.stats().counters.count("tracker_failures"), 1u);
  EXPECT_GE(mapper.stats().counters.at("tracker_failures"), 1u);
  bool failure_edge = false;
  for (const OdometryEdge& edge : mapper.edges()) failure_edge |= edge.after_tracker_failure;
  EXPECT_TRUE(failure_edge);
  for (const auto& pose : mapper.Trajectory()) EXPECT_TRUE(pose.pose.IsFinite());
}

// A person stands beside the route while the first node's stretch is driven and leaves when the
// node is made, so the node's cloud (a snapshot of the local map) holds them. The scans of the next
// stretch look through that place: once the next node is made, the finished node must not keep
// the person, and must keep the walls.
struct PersonInFinishedNode {
  int person_points = 0;
  std::size_t cloud_points = 0;
};

PersonInFinishedNode MapPastALeavingPerson(int clean_finished_nodes, int clean_moved_nodes) {
  const auto world = LongWorld();
  SyntheticLaser laser;
  laser.beams = 270;
  laser.fov_rad = 1.5 * M_PI;
  laser.range_noise_m = 0.01;
  const Eigen::Vector3d person(3.2, 1.5, 0.25);  // x, y, radius; the robot drives along y = 0.5
  MapperOptions options;
  options.tracker.clean_finished_nodes = clean_finished_nodes;
  options.tracker.clean_moved_nodes = clean_moved_nodes;
  Mapper mapper(options);
  std::vector<Pose2> truth;
  for (int i = 0; i < 50; ++i) {  // 6 m: the first node (at the start) made at 2.5 m, then 5 m
    truth.emplace_back(0.12 * i, 0.5, 0.0);
    std::vector<Eigen::Vector3d> people;
    if (mapper.nodes().empty()) people.push_back(person);
    ScanInput input;
    input.scan = CastScan(world, people, truth.back(), laser, 500 + i);
    input.scan.stamp_s = 0.1 * i;
    input.odom_T_base = truth.back();
    mapper.AddScan(input);
  }
  PersonInFinishedNode result;
  if (mapper.nodes().size() < 2) return result;
  // The mapper's frame against the world's, from the first scan's pose.
  const Pose2 map_T_world = mapper.Trajectory().front().pose * truth.front().inverse();
  const LocalMapNode& first = mapper.nodes().begin()->second;
  const Eigen::Vector2d person_in_node =
      first.map_T_node.inverse() * (map_T_world * Eigen::Vector2d(person.head<2>()));
  for (const RichPoint& p : first.cloud) {
    if ((p.point_m - person_in_node).norm() < person.z() + 0.1) ++result.person_points;
  }
  result.cloud_points = first.cloud.size();
  return result;
}

TEST(Mapper, AFinishedNodeForgetsWhatTheNextStretchSawThrough) {
  const PersonInFinishedNode kept = MapPastALeavingPerson(0, 0);
  const PersonInFinishedNode cleaned = MapPastALeavingPerson(1, 0);
  // The person stood still while the node was built: seen in place, not seen moving, so cleaning
  // only the seen-moving points of finished nodes leaves them (all but a few on its outline, where
  // scans from along the route fused points across its curve: 21 of 23 here).
  const PersonInFinishedNode moved_only = MapPastALeavingPerson(0, 3);
  std::printf(
      "person points in the finished node: %d of %zu kept, %d of %zu cleaned, %d of %zu with "
      "only seen-moving points cleaned\n",
      kept.person_points, kept.cloud_points, cleaned.person_points, cleaned.cloud_points,
      moved_only.person_points, moved_only.cloud_points);
  ASSERT_GE(kept.person_points, 5);  // the snapshot holds the person
  EXPECT_EQ(cleaned.person_points, 0);
  EXPECT_GE(moved_only.person_points, kept.person_points * 4 / 5);
  // Only the person (and a few grazing points) may go: the walls stay.
  EXPECT_GE(cleaned.cloud_points + kept.person_points, kept.cloud_points * 95 / 100);
  EXPECT_GE(moved_only.cloud_points, kept.cloud_points * 95 / 100);
}

TEST(Mapper, ScansGoingBackInTimeAreSkipped) {
  Drive drive = MakeDrive(10, 0.12, 8);
  drive.inputs[6].scan.stamp_s = 0.05;  // older than scans 1..5
  Mapper mapper(MapperOptions{});
  for (const auto& input : drive.inputs) mapper.AddScan(input);
  mapper.Finish();
  EXPECT_EQ(mapper.stats().scans_skipped.at("time_backwards"), 1u);
  EXPECT_EQ(mapper.stats().scans_processed, 9u);
  EXPECT_EQ(mapper.Trajectory().size(), 10u);
}

TEST(Mapper, BadScansAreSkippedWithAReasonAndKeepAPose) {
  Drive drive = MakeDrive(10, 0.12, 7);
  drive.inputs[3].scan.angle_increment_rad = 0.0;
  drive.inputs[5].scan.ranges.resize(10);
  for (float& r : drive.inputs[7].scan.ranges) r = std::numeric_limits<float>::quiet_NaN();
  Mapper mapper(MapperOptions{});
  for (const auto& input : drive.inputs) mapper.AddScan(input);
  mapper.Finish();
  EXPECT_EQ(mapper.stats().scans_skipped.at("invalid_geometry"), 1u);
  EXPECT_EQ(mapper.stats().scans_skipped.at("too_few_beams"), 1u);
  const auto trajectory = mapper.Trajectory();
  ASSERT_EQ(trajectory.size(), 10u);
  for (const auto& pose : trajectory) EXPECT_TRUE(pose.pose.IsFinite());
}

TEST(Mapper, ClockwiseScansAreTurnedRoundNotSkipped) {
  const Drive drive = MakeDrive(10, 0.12, 7);
  Drive clockwise = drive;
  for (auto& input : clockwise.inputs) {
    LaserScan& scan = input.scan;
    scan.angle_min_rad += scan.angle_increment_rad * static_cast<double>(scan.ranges.size() - 1);
    scan.angle_increment_rad = -scan.angle_increment_rad;
    std::reverse(scan.ranges.begin(), scan.ranges.end());
  }
  Mapper a(MapperOptions{}), b(MapperOptions{});
  for (const auto& input : drive.inputs) a.AddScan(input);
  for (const auto& input : clockwise.inputs) b.AddScan(input);
  a.Finish();
  b.Finish();
  EXPECT_EQ(b.stats().counters.at("scans_reversed"), 10u);
  EXPECT_EQ(b.stats().TotalSkipped(), a.stats().TotalSkipped());
  const auto ta = a.Trajectory(), tb = b.Trajectory();
  ASSERT_EQ(ta.size(), tb.size());
  for (std::size_t i = 0; i < ta.size(); ++i) {
    EXPECT_NEAR(ta[i].pose.x(), tb[i].pose.x(), 1e-6);
    EXPECT_NEAR(ta[i].pose.theta(), tb[i].pose.theta(), 1e-6);
  }
}

}  // namespace
}  // namespace longterm_mapper2d
