#pragma once

#include <ros/time.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"
#include "longterm_mapper2d/core/sensor/odometry_buffer.h"

namespace longterm_mapper2d_ros {

struct OpenedBags;

struct BagReaderOptions {
  std::string scan_topic = "/scan";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  // If set, odometry comes from this nav_msgs/Odometry topic instead of /tf.
  std::string odom_topic;
  // Window in seconds from the first message of the bags, like `rosbag play -s/-u`; end < 0 means
  // to the end.
  double start_s = 0.0;
  double end_s = -1.0;
  // A scan this close to the covered odometry interval takes its end pose.
  double odometry_tolerance_s = 0.5;
  // Scans are re-ordered by header stamp within this many messages.
  int reorder_window = 256;
};

struct BagReadStats {
  std::uint64_t scans_in_window = 0;
  std::uint64_t scans_emitted = 0;
  std::uint64_t scans_without_odometry = 0;
  std::uint64_t scans_out_of_order = 0;  // arrived later than a newer-stamped scan
  std::uint64_t odometry_samples = 0;
  bool laser_offset_found = true;
  double first_stamp_s = 0.0;
  double last_stamp_s = 0.0;
};

// Reads LaserScans from one or more bags with their odometry (from /tf odom_frame -> base_frame,
// chained through intermediate frames, or from a nav_msgs/Odometry topic) and the base -> laser
// offset (from /tf_static or /tf), and yields them as core ScanInputs in header stamp order.
// Odometry is loaded in a first pass; scans are streamed in the second, so memory stays bounded
// by the odometry, not the scans.
class BagScanSource {
 public:
  static longterm_mapper2d::StatusOr<std::unique_ptr<BagScanSource>> Open(
      const std::vector<std::string>& bag_paths, const BagReaderOptions& options);

  // Number of scans in the window (known after Open), for progress reporting.
  std::uint64_t scan_count() const { return stats_.scans_in_window; }
  // Calls `visit` for each scan in order. Scans without odometry coverage are counted, not
  // yielded. Returns an error if a bag cannot be read.
  longterm_mapper2d::Status ForEach(
      const std::function<void(const longterm_mapper2d::ScanInput&)>& visit);

  const BagReadStats& stats() const { return stats_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  BagScanSource(std::vector<std::string> bag_paths, BagReaderOptions options)
      : bag_paths_(std::move(bag_paths)), options_(std::move(options)) {}
  // The part of the recording (receive times) the passes read: all of it, or the window with a
  // margin, since header stamps and receive times differ a little.
  struct TimeSpan {
    ros::Time begin = ros::TIME_MIN;
    ros::Time end = ros::TIME_MAX;
    bool whole() const { return begin == ros::TIME_MIN && end == ros::TIME_MAX; }
  };
  static constexpr double kWindowMarginS = 30.0;

  longterm_mapper2d::Status LoadOdometry();
  TimeSpan ReadTimeSpan() const;
  // The first pass over `span`: odometry, laser mounts, scans in the window.
  longterm_mapper2d::Status LoadTransforms(const TimeSpan& span);

  std::vector<std::string> bag_paths_;
  BagReaderOptions options_;
  std::shared_ptr<OpenedBags> bags_;  // opened once, read by both passes
  longterm_mapper2d::OdometryBuffer odometry_;
  // base_T_laser per laser frame id.
  std::vector<std::pair<std::string, longterm_mapper2d::Pose2>> laser_offsets_;
  double window_begin_s_ = 0.0;
  double window_end_s_ = 0.0;
  BagReadStats stats_;
  std::vector<std::string> warnings_;
};

}  // namespace longterm_mapper2d_ros
