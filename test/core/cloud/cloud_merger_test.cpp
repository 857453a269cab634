#include "longterm_mapper2d/core/cloud/cloud_merger.h"

#include <gtest/gtest.h>

#include <limits>

#include "longterm_mapper2d/core/cloud/scan_to_cloud.h"
#include "testing/synthetic_scans.h"

namespace longterm_mapper2d {
namespace {

constexpr float kNoReturn = std::numeric_limits<float>::infinity();

// A scan of 5 beams straight ahead (1 degree apart) with the given ranges.
LaserScan FiveBeams(std::vector<float> ranges) {
  LaserScan scan;
  scan.angle_min_rad = -2.0 * M_PI / 180.0;
  scan.angle_increment_rad = M_PI / 180.0;
  scan.range_min_m = 0.05;
  scan.range_max_m = 20.0;
  scan.ranges = std::move(ranges);
  return scan;
}

RichPoint PointAhead(double range, double bearing_deg = 0.0, double weight = 1.0) {
  RichPoint p;
  const double a = bearing_deg * M_PI / 180.0;
  p.point_m = Eigen::Vector2d(range * std::cos(a), range * std::sin(a));
  p.normal = Eigen::Vector2d(-1.0, 0.0);
  p.weight = weight;
  return p;
}

// The new scan's points (laser at the origin, normals facing it) and their beams.
struct NewData {
  Cloud points;
  std::vector<int> beams;
};
NewData PointsOf(const LaserScan& scan) {
  NewData data;
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    if (!scan.IsValidRange(scan.ranges[i])) continue;
    data.points.push_back(PointAhead(scan.ranges[i], -2.0 + i, 1.0 / scan.ranges[i]));
    data.beams.push_back(static_cast<int>(i));
  }
  return data;
}

MergerOptions NoThinning() {
  MergerOptions options;
  options.radial_merge = false;
  return options;
}

TEST(CloudMerger, ABeamPassingThroughAnOldPointReplacesIt) {
  Cloud map = {PointAhead(3.0)};
  const LaserScan scan = FiveBeams({kNoReturn, kNoReturn, 5.0f, kNoReturn, kNoReturn});
  const NewData data = PointsOf(scan);
  CloudMerger merger(NoThinning());
  const MergeStats stats = merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  EXPECT_EQ(stats.replaced, 1);
  ASSERT_EQ(map.size(), 1u);
  EXPECT_NEAR(map[0].point_m.x(), 5.0, 1e-9);
}

TEST(CloudMerger, ANoReturnBeamErasesAnOldPointWithinTheFreeSpaceCap) {
  Cloud map = {PointAhead(3.0), PointAhead(15.0, 1.0)};
  const LaserScan scan = FiveBeams({kNoReturn, kNoReturn, kNoReturn, kNoReturn, kNoReturn});
  CloudMerger merger(NoThinning());
  const MergeStats stats = merger.Merge(map, {}, {}, scan, Pose2(), 30.0);
  // The point at 3 m is gone; the one at 15 m is beyond the 10 m cap and stays.
  EXPECT_EQ(stats.erased, 1);
  ASSERT_EQ(map.size(), 1u);
  EXPECT_NEAR(map[0].point_m.norm(), 15.0, 1e-9);
}

TEST(CloudMerger, AnObjectInFrontIsAddedAndTheWallKept) {
  Cloud map = {PointAhead(5.0)};
  const LaserScan scan = FiveBeams({kNoReturn, kNoReturn, 2.0f, kNoReturn, kNoReturn});
  const NewData data = PointsOf(scan);
  CloudMerger merger(NoThinning());
  const MergeStats stats = merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  EXPECT_EQ(stats.added, 1);
  EXPECT_EQ(map.size(), 2u);
}

TEST(CloudMerger, ClosePointsFuseWithInverseRangeWeights) {
  // Old point at 4.0 m seen from 4 m away (weight 1/4); the new one at 4.1 m (weight 1/4.1).
  Cloud map = {PointAhead(4.0, 0.0, 1.0 / 4.0)};
  const LaserScan scan = FiveBeams({kNoReturn, kNoReturn, 4.1f, kNoReturn, kNoReturn});
  const NewData data = PointsOf(scan);
  CloudMerger merger(NoThinning());
  const MergeStats stats = merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  EXPECT_EQ(stats.fused, 1);
  ASSERT_EQ(map.size(), 1u);
  const double w1 = 1.0 / 4.0, w2 = 1.0 / 4.1f;
  EXPECT_NEAR(map[0].point_m.x(), (w1 * 4.0 + w2 * 4.1f) / (w1 + w2), 1e-6);
  EXPECT_NEAR(map[0].weight, w1 + w2, 1e-6);
}

TEST(CloudMerger, UnobservedBinsAreUntouched) {
  // A point behind the laser (outside the 5-degree field of view) and one in a bin whose reading
  // is invalid (NaN) stay, even though nothing was seen there.
  Cloud map = {PointAhead(-3.0), PointAhead(3.0, 2.0)};
  const LaserScan scan = FiveBeams(
      {kNoReturn, kNoReturn, kNoReturn, kNoReturn, std::numeric_limits<float>::quiet_NaN()});
  CloudMerger merger(NoThinning());
  merger.Merge(map, {}, {}, scan, Pose2(), 30.0);
  EXPECT_EQ(map.size(), 2u);
}

TEST(CloudMerger, ObservationCountsGrowInPlaceAndDropWhenSomethingMoves) {
  CloudMerger merger(NoThinning());
  // An empty bin: a new point counts one observation.
  Cloud map;
  LaserScan scan = FiveBeams({kNoReturn, kNoReturn, 4.0f, kNoReturn, kNoReturn});
  NewData data = PointsOf(scan);
  merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  ASSERT_EQ(map.size(), 1u);
  EXPECT_EQ(map[0].observations, 1);
  // The same surface again, 1 cm off (range noise): fused, two observations.
  scan = FiveBeams({kNoReturn, kNoReturn, 4.01f, kNoReturn, kNoReturn});
  data = PointsOf(scan);
  merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  ASSERT_EQ(map.size(), 1u);
  EXPECT_EQ(map[0].observations, 2);
  // 0.1 m farther along the normal: still the same surface (within merge_distance_m, fused), but
  // off its line: it moved, and its count drops to 0.
  scan = FiveBeams({kNoReturn, kNoReturn, 4.11f, kNoReturn, kNoReturn});
  data = PointsOf(scan);
  const MergeStats stats = merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  EXPECT_EQ(stats.fused, 1);
  ASSERT_EQ(map.size(), 1u);
  EXPECT_EQ(map[0].observations, 0);
}

TEST(CloudMerger, AReturnKnownToMoveResetsTheCountInPlace) {
  // The motion filter marks a scan point as moving with 0 observations: fused in place, it still
  // leaves the surface unconfirmed (a slow walker moves less than the noise between two scans).
  CloudMerger merger(NoThinning());
  Cloud map;
  LaserScan scan = FiveBeams({kNoReturn, kNoReturn, 4.0f, kNoReturn, kNoReturn});
  NewData data = PointsOf(scan);
  merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  ASSERT_EQ(map.size(), 1u);
  ASSERT_EQ(map[0].observations, 2);
  data.points[0].observations = 0;
  const MergeStats stats = merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  EXPECT_EQ(stats.fused, 1);
  ASSERT_EQ(map.size(), 1u);
  EXPECT_EQ(map[0].observations, 0);
}

TEST(CloudMerger, PointsAppearingWhereABeamHadPassedStartUnconfirmed) {
  CloudMerger merger(NoThinning());
  // In front of a known wall (the space was seen free): 0 observations; the wall keeps its own.
  Cloud map = {PointAhead(5.0)};
  map[0].observations = 3;
  LaserScan scan = FiveBeams({kNoReturn, kNoReturn, 2.0f, kNoReturn, kNoReturn});
  NewData data = PointsOf(scan);
  merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  ASSERT_EQ(map.size(), 2u);
  EXPECT_EQ(map[0].observations, 3);
  EXPECT_EQ(map[1].observations, 0);
  // Behind an old point the beam passed through: the replacement has 0 observations too.
  map = {PointAhead(3.0)};
  scan = FiveBeams({kNoReturn, kNoReturn, 5.0f, kNoReturn, kNoReturn});
  data = PointsOf(scan);
  merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  ASSERT_EQ(map.size(), 1u);
  EXPECT_EQ(map[0].observations, 0);
}

TEST(CloudMerger, WithoutFreeSpaceReasoningNothingIsReplacedOrErased) {
  MergerOptions options = NoThinning();
  options.free_space_reasoning = false;
  CloudMerger merger(options);
  // A beam through an old point adds the new return behind it; a no-return beam erases nothing.
  Cloud map = {PointAhead(3.0), PointAhead(3.0, 1.0)};
  const LaserScan scan = FiveBeams({kNoReturn, kNoReturn, 5.0f, kNoReturn, kNoReturn});
  const NewData data = PointsOf(scan);
  const MergeStats stats = merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0);
  EXPECT_EQ(stats.added, 1);
  EXPECT_EQ(stats.replaced, 0);
  EXPECT_EQ(stats.erased, 0);
  EXPECT_EQ(map.size(), 3u);
}

// A finished node's cloud takes no new points, only free space: a point is erased where a beam
// ended behind it (a return or a no-return), kept where the beam ended at or before it, and
// untouched where the reading observed nothing.
TEST(CloudMerger, EraseSeenThroughRemovesOnlyWhatABeamPassed) {
  const Cloud before = {PointAhead(3.0, -2.0), PointAhead(3.0, -1.0), PointAhead(3.0, 0.0),
                        PointAhead(3.0, 1.0), PointAhead(3.0, 2.0)};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Beam 0 ended behind the point, beam 1 is a no-return, beam 2 ended on it, beam 3 in front of
  // it, beam 4 observed nothing.
  const LaserScan scan = FiveBeams({5.0f, kNoReturn, 3.05f, 1.0f, nan});
  Cloud map = before;
  CloudMerger merger(NoThinning());
  EXPECT_EQ(merger.EraseSeenThrough(map, scan, Pose2(), 100), 2);
  ASSERT_EQ(map.size(), 3u);
  EXPECT_NEAR(map[0].point_m.y(), before[2].point_m.y(), 1e-12);
  EXPECT_NEAR(map[1].point_m.y(), before[3].point_m.y(), 1e-12);
  EXPECT_NEAR(map[2].point_m.y(), before[4].point_m.y(), 1e-12);
  // Points seen in place more often than the limit stay.
  map = before;
  for (RichPoint& p : map) p.observations = 5;
  EXPECT_EQ(merger.EraseSeenThrough(map, scan, Pose2(), 4), 0);
  EXPECT_EQ(map.size(), before.size());
}

TEST(CloudMerger, FusedWeightsSaturate) {
  RichPoint a = PointAhead(1.0, 0.0, 900.0), b = PointAhead(1.0, 0.0, 300.0);
  EXPECT_DOUBLE_EQ(Fuse(a, b, 1000.0).weight, 1000.0);
}

TEST(CloudMerger, APointSeenAgainIsNoLongerInherited) {
  RichPoint inherited = PointAhead(1.0), own = PointAhead(1.0);
  inherited.inherited = true;
  EXPECT_FALSE(Fuse(inherited, own, 1000.0).inherited);
  EXPECT_FALSE(Fuse(own, inherited, 1000.0).inherited);
  EXPECT_TRUE(Fuse(inherited, inherited, 1000.0).inherited);

  // In a merge: the old point the new return fuses with becomes the map's own; one the scan did
  // not observe stays inherited.
  Cloud map = {PointAhead(4.0, 0.0, 0.25), PointAhead(5.0, 20.0, 0.2)};
  for (RichPoint& p : map) p.inherited = true;
  const LaserScan scan = FiveBeams({kNoReturn, kNoReturn, 4.05f, kNoReturn, kNoReturn});
  const NewData data = PointsOf(scan);
  CloudMerger merger(NoThinning());
  EXPECT_EQ(merger.Merge(map, data.points, data.beams, scan, Pose2(), 30.0).fused, 1);
  ASSERT_EQ(map.size(), 2u);
  for (const RichPoint& p : map)
    EXPECT_EQ(p.inherited, p.point_m.y() != 0.0) << p.point_m.transpose();
}

TEST(CloudMerger, APersonCrossingACorridorLeavesNoTrace) {
  // A corridor seen by a laser that stands still in it; a person walks across in front of it.
  const auto corridor = test_support::Corridor();
  test_support::SyntheticLaser laser;
  laser.beams = 360;
  const CloudOptions cloud_options;
  CloudMerger merger(MergerOptions{});
  Cloud map;
  const Pose2 laser_pose(0.0, 0.0, 0.0);
  std::vector<Eigen::Vector2d> person_positions;
  for (int step = 0; step <= 40; ++step) {
    // The person walks from y = -0.6 to 0.6 at x = 2, then is gone for the last scans.
    std::vector<Eigen::Vector3d> people;
    if (step < 30) {
      const Eigen::Vector2d p(2.0, -0.6 + 1.2 * step / 29.0);
      people.emplace_back(p.x(), p.y(), 0.2);
      person_positions.push_back(p);
    }
    const LaserScan scan = test_support::CastScan(corridor, people, laser_pose, laser, step);
    std::vector<int> beams;
    const Cloud points = CloudFromScan(scan, Pose2(), cloud_options, &beams);
    merger.Merge(map, points, beams, scan, laser_pose, 30.0);
  }
  // No point remains where the person was (away from the walls)...
  int near_person = 0;
  for (const RichPoint& p : map) {
    if (std::abs(p.point_m.y()) > 0.9) continue;
    for (const Eigen::Vector2d& position : person_positions) {
      if ((p.point_m - position).norm() < 0.25) {
        ++near_person;
        break;
      }
    }
  }
  EXPECT_EQ(near_person, 0);
  // ... and the walls are intact: points along both walls on either side.
  int left = 0, right = 0;
  for (const RichPoint& p : map) {
    if (std::abs(p.point_m.y() - 1.0) < 0.05) ++left;
    if (std::abs(p.point_m.y() + 1.0) < 0.05) ++right;
  }
  EXPECT_GT(left, 50);
  EXPECT_GT(right, 50);
}

}  // namespace
}  // namespace longterm_mapper2d
