#include "longterm_mapper2d/ros/bag_scan_source.h"

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <cstdio>

#include "longterm_mapper2d/ros/conversions.h"

namespace longterm_mapper2d_ros {
namespace {

using longterm_mapper2d::Pose2;
using longterm_mapper2d::ScanInput;

geometry_msgs::TransformStamped Transform(const Pose2& pose, double stamp,
                                          const std::string& parent, const std::string& child) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time(stamp);
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform = ToRosTransform(pose);
  return t;
}

sensor_msgs::LaserScan Scan(double stamp, const std::string& frame) {
  sensor_msgs::LaserScan scan;
  scan.header.stamp = ros::Time(stamp);
  scan.header.frame_id = frame;
  scan.angle_min = -M_PI / 2;
  scan.angle_increment = M_PI / 180;
  scan.angle_max = scan.angle_min + 179 * scan.angle_increment;
  scan.range_min = 0.1;
  scan.range_max = 30.0;
  scan.ranges.assign(180, 2.0f);
  return scan;
}

std::string TempBag(const char* name) {
  return std::string("/tmp/ltm_bag_test_") + std::to_string(::getpid()) + "_" + name + ".bag";
}

// Odometry on /tf through base_footprint (odom -> base_footprint -> base_link), the laser mount on
// /tf_static, and scans written out of stamp order.
std::string WriteTfBag() {
  const std::string path = TempBag("tf");
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  tf2_msgs::TFMessage statics;
  statics.transforms.push_back(Transform(Pose2(0.22, 0.0, 0.0), 100.0, "base_link", "laser"));
  statics.transforms.push_back(Transform(Pose2(), 100.0, "base_footprint", "base_link"));
  bag.write("/tf_static", ros::Time(100.0), statics);
  for (int i = 0; i <= 20; ++i) {
    const double t = 100.0 + 0.1 * i;
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(Transform(Pose2(0.05 * i, 0.0, 0.01 * i), t, "odom", "base_footprint"));
    bag.write("/tf", ros::Time(t), tf);
  }
  // Scans at 100.25, 100.15 (late), 100.55, and one after the odometry ends (103.0).
  for (double t : {100.25, 100.15, 100.55, 103.0})
    bag.write("/scan", ros::Time(t + 0.02), Scan(t, "laser"));
  bag.close();
  return path;
}

TEST(BagScanSource, ReadsScansInStampOrderWithChainedOdometryAndTheLaserMount) {
  const std::string path = WriteTfBag();
  BagReaderOptions options;
  auto source = BagScanSource::Open({path}, options);
  ASSERT_TRUE(source.ok()) << source.status().message();
  std::vector<ScanInput> scans;
  ASSERT_TRUE((*source)->ForEach([&](const ScanInput& s) { scans.push_back(s); }).ok());
  ASSERT_EQ(scans.size(), 3u);  // the scan without odometry is counted, not yielded
  EXPECT_EQ((*source)->stats().scans_without_odometry, 1u);
  EXPECT_DOUBLE_EQ(scans[0].scan.stamp_s, 100.15);
  EXPECT_DOUBLE_EQ(scans[1].scan.stamp_s, 100.25);
  // Interpolated odometry: x = 0.5 (t - 100), theta = 0.1 (t - 100).
  EXPECT_NEAR(scans[1].odom_T_base.x(), 0.125, 1e-6);
  EXPECT_NEAR(scans[1].odom_T_base.theta(), 0.025, 1e-6);
  EXPECT_NEAR(scans[2].base_T_laser.x(), 0.22, 1e-9);
  EXPECT_EQ(scans[2].scan.ranges.size(), 180u);
  std::remove(path.c_str());
}

TEST(BagScanSource, TakesOdometryFromAnOdometryTopicAndHonoursTheTimeWindow) {
  const std::string path = TempBag("odom");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    for (int i = 0; i <= 30; ++i) {
      const double t = 50.0 + 0.1 * i;
      nav_msgs::Odometry odom;
      odom.header.stamp = ros::Time(t);
      odom.pose.pose.position.x = 1.0 * i;
      odom.pose.pose.orientation.w = 1.0;
      bag.write("/odom", ros::Time(t), odom);
      if (i % 5 == 0) bag.write("/base_scan", ros::Time(t), Scan(t, "base_link"));
    }
  }
  BagReaderOptions options;
  options.scan_topic = "/base_scan";
  options.odom_topic = "/odom";
  options.start_s = 0.9;  // seconds from the first message
  options.end_s = 2.6;
  auto source = BagScanSource::Open({path}, options);
  ASSERT_TRUE(source.ok()) << source.status().message();
  std::vector<double> stamps;
  ASSERT_TRUE((*source)
                  ->ForEach([&](const ScanInput& s) {
                    stamps.push_back(s.scan.stamp_s);
                    EXPECT_NEAR(s.odom_T_base.x(), 10.0 * (s.scan.stamp_s - 50.0), 1e-6);
                  })
                  .ok());
  // Scans every 0.5 s from 50.0: the window [50.9, 52.6) holds 51.0, 51.5, 52.0 and 52.5.
  ASSERT_EQ(stamps.size(), 4u);
  EXPECT_DOUBLE_EQ(stamps.front(), 51.0);
  EXPECT_DOUBLE_EQ(stamps.back(), 52.5);
  std::remove(path.c_str());
}

// 200 s of odometry on /tf at 10 Hz and a scan every second; the laser mount either on
// /tf_static or sent once on /tf at the start.
std::string WriteLongBag(const char* name, bool mount_on_tf_static) {
  const std::string path = TempBag(name);
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  tf2_msgs::TFMessage mount;
  mount.transforms.push_back(Transform(Pose2(0.22, 0.0, 0.0), 1000.0, "base_link", "laser"));
  bag.write(mount_on_tf_static ? "/tf_static" : "/tf", ros::Time(1000.0), mount);
  for (int i = 1; i <= 2000; ++i) {
    const double t = 1000.0 + 0.1 * i;
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(Transform(Pose2(0.01 * i, 0.0, 0.0), t, "odom", "base_link"));
    bag.write("/tf", ros::Time(t), tf);
    if (i % 10 == 5) bag.write("/scan", ros::Time(t), Scan(t, "laser"));
  }
  bag.close();
  return path;
}

TEST(BagScanSource, AWindowOfALongRecordingReadsAroundTheWindowAndFindsAMountSentBefore) {
  for (const bool mount_on_tf_static : {true, false}) {
    SCOPED_TRACE(mount_on_tf_static ? "mount on /tf_static" : "mount once on /tf");
    const std::string path = WriteLongBag("long", mount_on_tf_static);
    BagReaderOptions options;
    options.start_s = 150.0;
    options.end_s = 170.0;
    auto source = BagScanSource::Open({path}, options);
    ASSERT_TRUE(source.ok()) << source.status().message();
    EXPECT_TRUE((*source)->stats().laser_offset_found);
    EXPECT_EQ((*source)->scan_count(), 20u);
    std::vector<ScanInput> scans;
    ASSERT_TRUE((*source)->ForEach([&](const ScanInput& s) { scans.push_back(s); }).ok());
    ASSERT_EQ(scans.size(), 20u);
    EXPECT_NEAR(scans.front().scan.stamp_s, 1150.5, 1e-6);
    for (const ScanInput& s : scans) {
      EXPECT_NEAR(s.odom_T_base.x(), 0.1 * (s.scan.stamp_s - 1000.0), 1e-6);
      EXPECT_NEAR(s.base_T_laser.x(), 0.22, 1e-9);
    }
    // With the mount on /tf_static only the window and 30 s either side are read (80 s of the
    // 200); a mount sent once on /tf before the window takes a read of the whole recording.
    if (mount_on_tf_static) {
      EXPECT_LE((*source)->stats().odometry_samples, 801u);
    } else {
      EXPECT_EQ((*source)->stats().odometry_samples, 2000u);
    }
    std::remove(path.c_str());
  }
}

TEST(BagScanSource, ClearErrorsForMissingFilesAndMissingOdometry) {
  BagReaderOptions options;
  auto missing = BagScanSource::Open({"/nonexistent/file.bag"}, options);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("/nonexistent/file.bag"), std::string::npos);

  const std::string path = WriteTfBag();
  options.odom_frame = "wrong_odom";
  auto no_odometry = BagScanSource::Open({path}, options);
  ASSERT_FALSE(no_odometry.ok());
  EXPECT_NE(no_odometry.status().message().find("wrong_odom"), std::string::npos);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace longterm_mapper2d_ros
