#include "longterm_mapper2d/core/io/carmen_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace longterm_mapper2d {
namespace {

std::string Readings(int n, double value) {
  std::ostringstream out;
  for (int i = 0; i < n; ++i) out << value << ' ';
  return out.str();
}

std::string Flaser(int n, double range, double stamp, const std::string& laser_pose,
                   const std::string& odom_pose) {
  std::ostringstream out;
  out << "FLASER " << n << ' ' << Readings(n, range) << laser_pose << ' ' << odom_pose << ' '
      << std::fixed << stamp << " nohost 0.0\n";
  return out.str();
}

TEST(CarmenReader, ReadsFlaserWithOldBeamGeometryAndInterpolatedOdometry) {
  std::string text = "# a comment\n";
  text += "ODOM 0 0 0 0 0 0 10.0 nohost 0\n";
  text += "ODOM 1 0 0.2 0 0 0 11.0 nohost 0\n";
  text += Flaser(180, 2.0, 10.5, "0 0 0", "0 0 0");
  text += Flaser(361, 3.0, 10.75, "0.5 0 0", "0.5 0 0");
  text += "PARAM robot_name x\n";
  const auto log = ParseCarmenLog(text, "test.clf");
  ASSERT_TRUE(log.ok()) << log.status().message();
  ASSERT_EQ(log->scans.size(), 2u);
  const LaserScan& a = log->scans[0].scan;
  EXPECT_EQ(a.ranges.size(), 180u);
  EXPECT_DOUBLE_EQ(a.angle_min_rad, -M_PI / 2);
  EXPECT_DOUBLE_EQ(a.angle_increment_rad, M_PI / 180);
  EXPECT_DOUBLE_EQ(a.stamp_s, 10.5);
  EXPECT_NEAR(log->scans[0].odom_T_base.x(), 0.5, 1e-12);
  EXPECT_NEAR(log->scans[0].odom_T_base.theta(), 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(log->scans[1].scan.angle_increment_rad, M_PI / 360);
  EXPECT_NEAR(log->scans[1].odom_T_base.x(), 0.75, 1e-12);
  EXPECT_EQ(log->skipped_messages.at("PARAM"), 1u);
  EXPECT_EQ(log->scans_with_line_odometry, 0u);
}

TEST(CarmenReader, FiltersSaturatedNoReturnReadings) {
  std::string text;
  // Every scan has beams at 81.83 (the log's no-return value) and real returns.
  for (int k = 0; k < 3; ++k) {
    std::ostringstream line;
    line << "FLASER 180 " << Readings(170, 4.0) << Readings(10, 81.83) << "0 0 0 0 0 0 "
         << 100 + k << " nohost 0\n";
    text += line.str();
  }
  const auto log = ParseCarmenLog(text, "test.clf");
  ASSERT_TRUE(log.ok()) << log.status().message();
  EXPECT_NEAR(log->no_return_range_m, 81.83, 1e-4);
  EXPECT_EQ(log->readings_no_return, 30u);
  const LaserScan& scan = log->scans[0].scan;
  EXPECT_TRUE(scan.IsValidRange(scan.ranges[0]));
  EXPECT_TRUE(std::isinf(scan.ranges[175]));
  EXPECT_FALSE(scan.IsValidRange(scan.ranges[175]));
  // Without ODOM records the line's own odometry pose is used.
  EXPECT_EQ(log->scans_with_line_odometry, 3u);
}

TEST(CarmenReader, RobotLaserGivesAnglesAndTheLaserOffset) {
  std::ostringstream line;
  // laser_type start fov resolution max_range accuracy remission_mode n readings
  line << "ROBOTLASER1 0 -1.5708 3.14159 0.0174533 30.0 0.01 0 181 " << Readings(181, 5.0)
       << "0 "                           // no remissions
       << "1.22 2.0 0.0 1.0 2.0 0.0 "    // laser pose, robot pose (laser 0.22 m ahead)
       << "0 0 0.5 0.5 0.0 "             // tv rv safety distances turn axis
       << "50.0 nohost 0.0\n";
  const auto log = ParseCarmenLog(line.str(), "robot.log");
  ASSERT_TRUE(log.ok()) << log.status().message();
  ASSERT_EQ(log->scans.size(), 1u);
  const ScanInput& input = log->scans[0];
  EXPECT_NEAR(input.scan.angle_min_rad, -1.5708, 1e-9);
  EXPECT_NEAR(input.scan.angle_increment_rad, 3.14159 / 180, 1e-9);
  EXPECT_NEAR(input.scan.range_max_m, 30.0, 1e-9);
  EXPECT_NEAR(input.base_T_laser.x(), 0.22, 1e-9);
  EXPECT_NEAR(input.base_T_laser.y(), 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(input.scan.stamp_s, 50.0);
}

TEST(CarmenReader, MalformedLinesNameTheLine) {
  auto log = ParseCarmenLog("ODOM 0 0 0 0 0 0 1 h 0\nFLASER 180 1 2 3\n", "bad.clf");
  ASSERT_FALSE(log.ok());
  EXPECT_NE(log.status().message().find("bad.clf:2:"), std::string::npos)
      << log.status().message();
  log = ParseCarmenLog("ODOM 0 zero 0 0 0 0 1 h 0\n", "bad.clf");
  ASSERT_FALSE(log.ok());
  EXPECT_NE(log.status().message().find("bad.clf:1: malformed ODOM"), std::string::npos);
  log = ParseCarmenLog("FLASER -3\n", "bad.clf");
  EXPECT_FALSE(log.ok());
  EXPECT_FALSE(ReadCarmenLog("/nonexistent/log.clf").ok());
}

TEST(CarmenReader, PlaceholderOdomRecordsFallBackToTheLineOdometry) {
  // ODOM records that never move (a log writer's placeholders): the FLASER odometry is used.
  std::string text = "ODOM 0 0 0 0 0 0 1.0 h 0\nODOM 0 0 0 0 0 0 3.0 h 0\n";
  text += Flaser(180, 2.0, 2.0, "5 1 0.5", "0.7 0.2 0.1");
  const auto log = ParseCarmenLog(text, "placeholder.log");
  ASSERT_TRUE(log.ok()) << log.status().message();
  EXPECT_FALSE(log->odom_records_used);
  EXPECT_NEAR(log->scans[0].odom_T_base.x(), 0.7, 1e-12);
  EXPECT_EQ(log->scans_with_line_odometry, 1u);
}

TEST(CarmenReader, SortsRecordsByTime) {
  std::string text = Flaser(180, 2.0, 20.0, "0 0 0", "0 0 0");
  text += Flaser(180, 2.0, 10.0, "0 0 0", "0 0 0");
  const auto log = ParseCarmenLog(text, "t.clf");
  ASSERT_TRUE(log.ok());
  EXPECT_LT(log->scans[0].scan.stamp_s, log->scans[1].scan.stamp_s);
}

// Found by test/fuzz/carmen_fuzzer: "1e384" (also "nan", "inf") in a pose or stamp field parsed
// as a non-finite number and gave the scan a non-finite pose. Poses so large that the laser
// offset or the interpolated odometry overflows are refused too.
TEST(CarmenReader, NonFinitePosesAndStampsAreMalformed) {
  const struct {
    const char* text;
    const char* expected;
  } cases[] = {
      {"FLASER 1 6 1 2 4 9 2 1e384 1", "bad.clf:1: FLASER record lacks finite laser and robot"},
      {"FLASER 1 1.0 0 0 0 nan 0 0 5.0 h 0\n", "bad.clf:1: FLASER record lacks finite laser"},
      {"FLASER 1 1.0 0 0 0 0 0 0 inf h 0\n", "bad.clf:1: FLASER record lacks a finite timestamp"},
      {"ODOM 0 nan 0 0 0 0 1.0 h 0\n", "bad.clf:1: malformed ODOM"},
      {"FLASER 1 1.0 1e308 1e308 0.78 -1e308 -1e308 0 5.0 h 0\n",
       "bad.clf:1: FLASER record: laser"},
      {"ODOM 0 0 0 0 0 0 -1e308 h 0\nODOM 1 0 0 0 0 0 1e308 h 0\n"
       "FLASER 1 1.0 0 0 0 0 0 0 0.9e308 h 0\n",
       "bad.clf:3: odometry interpolated at the scan stamp is not finite"},
  };
  for (const auto& c : cases) {
    const auto log = ParseCarmenLog(c.text, "bad.clf");
    ASSERT_FALSE(log.ok()) << c.text;
    EXPECT_NE(log.status().message().find(c.expected), std::string::npos) << log.status().message();
  }
}

}  // namespace
}  // namespace longterm_mapper2d
