#include "longterm_mapper2d/core/cloud/range_projector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "longterm_mapper2d/core/cloud/scan_to_cloud.h"

namespace longterm_mapper2d {
namespace {

RichPoint At(double x, double y, Eigen::Vector2d normal = Eigen::Vector2d::Zero()) {
  RichPoint p;
  p.point_m = Eigen::Vector2d(x, y);
  p.normal = normal;
  return p;
}

TEST(RangeProjector, FullCircleWrapsAroundPi) {
  const auto g = ProjectorGeometry::FullCircle(360, 30.0);
  EXPECT_TRUE(g.wraps);
  EXPECT_EQ(g.BinOf(-M_PI), 0);
  EXPECT_EQ(g.BinOf(M_PI), 0);  // the same direction
  EXPECT_EQ(g.BinOf(M_PI - 0.001), 0);
  EXPECT_EQ(g.Shift(0, -1), 359);
  EXPECT_EQ(g.Shift(359, 2), 1);
}

TEST(RangeProjector, RoundingMatchesTheLibrary) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> value(-2000.0, 2000.0);
  std::vector<double> xs = {0.0, -0.0, 0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 0.49999999999999994,
                            -0.49999999999999994, 719.5, 1e16, -1e16, 4503599627370497.0};
  for (int i = 0; i < 100000; ++i) xs.push_back(value(rng));
  for (int i = 0; i < 1000; ++i) xs.push_back(std::round(value(rng)) + 0.5);
  for (double x : xs) ASSERT_EQ(ProjectorGeometry::RoundHalfAway(x), std::lround(x)) << x;
}

TEST(RangeProjector, BinsFollowTheScanGeometry) {
  LaserScan scan;
  scan.angle_min_rad = -M_PI / 2;
  scan.angle_increment_rad = M_PI / 180;
  scan.range_max_m = 80;
  scan.ranges.assign(180, 1.0f);
  const auto g = ProjectorGeometry::FromScan(scan, 30.0);
  EXPECT_FALSE(g.wraps);
  EXPECT_EQ(g.num_bins, 180);
  EXPECT_EQ(g.BinOf(-M_PI / 2), 0);
  EXPECT_EQ(g.BinOf(scan.BeamAngle(17)), 17);
  EXPECT_EQ(g.BinOf(M_PI), -1);  // behind
  EXPECT_EQ(g.Shift(0, -1), -1);
}

TEST(RangeProjector, ZBufferKeepsTheNearestAndBackFacesOcclude) {
  const auto g = ProjectorGeometry::FullCircle(360, 30.0);
  RangeImage image;
  // Two points on the same ray: the nearer wins. A back-facing point in front of a third occludes
  // it without being matchable.
  const Cloud cloud = {At(3.0, 0.0, {-1, 0}), At(2.0, 0.0, {-1, 0}),
                       At(0.0, 4.0, {0, -1}), At(0.0, 2.0, {0, 1})};
  ProjectCloud(g, Pose2(), cloud, &image);
  const int ahead = g.BinOf(0.0), left = g.BinOf(M_PI / 2);
  EXPECT_EQ(image.indices[ahead], 1);
  EXPECT_FLOAT_EQ(image.ranges_m[ahead], 2.0f);
  EXPECT_EQ(image.indices[left], -1);
  EXPECT_EQ(image.nearest[left], 3);
  EXPECT_FLOAT_EQ(image.ranges_m[left], 2.0f);
  // Seen from a viewpoint 1 m ahead, the first points are 1 m and 2 m away.
  ProjectCloud(g, Pose2(1.0, 0.0, 0.0).inverse(), cloud, &image);
  EXPECT_FLOAT_EQ(image.ranges_m[ahead], 1.0f);
}

// A wall across the laser's view at x = distance_m, seen by 181 beams over 180 degrees (1 degree
// apart); the beams turned from it by more than acos(min_cos) see nothing (infinite range).
LaserScan WallScan(double distance_m, double min_cos, float range_max_m) {
  LaserScan scan;
  scan.angle_min_rad = -M_PI / 2;
  scan.angle_increment_rad = M_PI / 180;
  scan.range_min_m = 0.05;
  scan.range_max_m = range_max_m;
  for (int i = 0; i < 181; ++i) {
    const double a = scan.BeamAngle(i);
    scan.ranges.push_back(std::cos(a) > min_cos ? static_cast<float>(distance_m / std::cos(a))
                                                : std::numeric_limits<float>::infinity());
  }
  return scan;
}

TEST(ScanToCloud, NormalsFaceTheLaserAndCornersHaveNone) {
  // A wall at x = 2: normals point back at the laser (-x).
  const LaserScan scan = WallScan(2.0, 0.2, 20.0f);
  const Pose2 base_T_laser(0.3, 0.0, 0.0);
  std::vector<int> beams;
  const Cloud cloud = CloudFromScan(scan, base_T_laser, CloudOptions{}, &beams);
  ASSERT_GT(cloud.size(), 100u);
  EXPECT_EQ(beams.size(), cloud.size());
  int with_normal = 0;
  for (const RichPoint& p : cloud) {
    EXPECT_NEAR(p.point_m.x(), 2.3, 1e-5);  // the mount offset is applied
    if (p.has_normal()) {
      ++with_normal;
      EXPECT_NEAR(p.normal.x(), -1.0, 1e-6);
    }
    EXPECT_NEAR(p.weight, 1.0 / (p.point_m - base_T_laser.translation()).norm(), 1e-5);
  }
  EXPECT_GT(with_normal, 100);
  // Isolated returns (fewer than 5 neighbours within 0.3 m) get no normal.
  LaserScan sparse = scan;
  for (std::size_t i = 0; i < sparse.ranges.size(); ++i) {
    if (i % 10 != 0) sparse.ranges[i] = std::numeric_limits<float>::quiet_NaN();
  }
  for (const RichPoint& p : CloudFromScan(sparse, Pose2(), CloudOptions{})) {
    EXPECT_FALSE(p.has_normal());
  }
}

TEST(ScanToCloud, FarWallsOfALargeHallKeepTheirNormals) {
  // A wall 20 m away seen by a laser with 1 degree between beams: its returns are 0.35 m apart or
  // more, so a fixed 0.3 m neighbourhood (the default) holds one point and gives no normal; the
  // neighbourhood that grows with the beams' spacing gives the wall its normal.
  const LaserScan scan = WallScan(20.0, 0.7, 80.0f);
  CloudOptions fixed;
  fixed.normal_radius_beams = 0.0;
  const Cloud without = CloudFromScan(scan, Pose2(), fixed);
  ASSERT_GT(without.size(), 80u);
  for (const RichPoint& p : without) EXPECT_FALSE(p.has_normal());

  CloudOptions growing;
  growing.normal_radius_beams = 3.0;
  const Cloud with = CloudFromScan(scan, Pose2(), growing);
  ASSERT_EQ(with.size(), without.size());
  int with_normal = 0;
  for (const RichPoint& p : with) {
    if (!p.has_normal()) continue;
    ++with_normal;
    EXPECT_NEAR(p.normal.x(), -1.0, 1e-6);
  }
  // Within 45 deg of the wall's normal the returns are at most 3 / sqrt(2) beam spacings apart
  // along the wall: all but the two at each end of the wall have enough neighbours.
  EXPECT_GE(with_normal, static_cast<int>(with.size()) - 4);
}

}  // namespace
}  // namespace longterm_mapper2d
