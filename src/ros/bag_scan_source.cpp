#include "longterm_mapper2d/ros/bag_scan_source.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <set>

#include "longterm_mapper2d/ros/conversions.h"

namespace longterm_mapper2d_ros {

using longterm_mapper2d::Pose2;
using longterm_mapper2d::ScanInput;
using longterm_mapper2d::Status;
using longterm_mapper2d::StatusOr;

struct OpenedBags {
  std::vector<std::unique_ptr<rosbag::Bag>> bags;
  ros::Time begin = ros::TIME_MAX;
  ros::Time end = ros::TIME_MIN;
};

namespace {

StatusOr<std::shared_ptr<OpenedBags>> OpenAll(const std::vector<std::string>& paths) {
  auto open = std::make_shared<OpenedBags>();
  for (const auto& path : paths) {
    auto bag = std::make_unique<rosbag::Bag>();
    try {
      bag->open(path, rosbag::bagmode::Read);
      // An empty view begins at TIME_MAX and ends at TIME_MIN (size() would walk the whole index).
      rosbag::View everything(*bag);
      open->begin = std::min(open->begin, everything.getBeginTime());
      open->end = std::max(open->end, everything.getEndTime());
    } catch (const std::exception& e) {
      return Status::Error("cannot read bag '" + path + "': " + e.what());
    }
    open->bags.push_back(std::move(bag));
  }
  if (open->begin > open->end) return Status::Error("the bags contain no messages");
  return open;
}

}  // namespace

StatusOr<std::unique_ptr<BagScanSource>> BagScanSource::Open(
    const std::vector<std::string>& bag_paths, const BagReaderOptions& options) {
  if (bag_paths.empty()) return Status::Error("no bag given");
  std::unique_ptr<BagScanSource> source(new BagScanSource(bag_paths, options));
  if (Status s = source->LoadOdometry(); !s.ok()) return s;
  return source;
}

Status BagScanSource::LoadOdometry() {
  auto opened = OpenAll(bag_paths_);
  if (!opened.ok()) return opened.status();
  bags_ = *opened;
  const double bag_begin_s = bags_->begin.toSec();
  window_begin_s_ = bag_begin_s + std::max(0.0, options_.start_s);
  window_end_s_ =
      options_.end_s < 0.0 ? std::numeric_limits<double>::infinity() : bag_begin_s + options_.end_s;
  // A window of a long recording reads the recording's /tf, odometry and scans only around the
  // window (a ten-hour bag mapped an hour at a time would otherwise read all ten hours each time).
  // If that leaves the odometry or a laser mount unresolved (a mount sent once on /tf, long
  // before the window), the whole recording is read after all.
  const TimeSpan window = ReadTimeSpan();
  if (!window.whole() && LoadTransforms(window).ok() && !laser_offsets_.empty() &&
      stats_.laser_offset_found) {
    return Status::Ok();
  }
  return LoadTransforms(TimeSpan{});
}

BagScanSource::TimeSpan BagScanSource::ReadTimeSpan() const {
  TimeSpan span;
  if (options_.start_s <= 0.0 && options_.end_s < 0.0) return span;
  const double latest_s = ros::TIME_MAX.toSec();
  span.begin = ros::Time(std::clamp(window_begin_s_ - kWindowMarginS, 0.0, latest_s));
  span.end = window_end_s_ + kWindowMarginS < latest_s ? ros::Time(window_end_s_ + kWindowMarginS)
                                                       : ros::TIME_MAX;
  return span;
}

Status BagScanSource::LoadTransforms(const TimeSpan& span) {
  odometry_ = longterm_mapper2d::OdometryBuffer();
  laser_offsets_.clear();
  warnings_.clear();
  stats_ = BagReadStats();

  // All transforms go into one tf2 buffer that covers the span read, so that chains
  // (odom -> base_footprint -> base_link) and the static laser mount resolve as a node would.
  const ros::Time first = std::max(span.begin, bags_->begin);
  const ros::Time last = std::min(span.end, bags_->end);
  const double duration_s = std::max(0.0, (last - first).toSec());
  auto buffer = std::make_shared<tf2::BufferCore>(ros::Duration(duration_s + 60.0));
  std::vector<double> chain_stamps;
  std::set<std::string> laser_frames;
  std::map<std::string, double> last_stamp_by_child;
  try {
    rosbag::View view;
    for (auto& bag : bags_->bags) {
      const std::vector<std::string> topics{"/tf", options_.odom_topic, options_.scan_topic};
      view.addQuery(*bag, rosbag::TopicQuery(topics), span.begin, span.end);
      // Static transforms are latched at the start of a recording: always read them all.
      view.addQuery(*bag, rosbag::TopicQuery("/tf_static"));
    }
    for (const rosbag::MessageInstance& message : view) {
      if (auto tf = message.instantiate<tf2_msgs::TFMessage>()) {
        const bool is_static = message.getTopic() == "/tf_static";
        for (const auto& transform : tf->transforms) {
          // tf2 warns on every repeated stamp; a recording may repeat one, keep the first.
          double& last_stamp = last_stamp_by_child[transform.child_frame_id];
          const double stamp = transform.header.stamp.toSec();
          if (!is_static && stamp == last_stamp) continue;
          last_stamp = stamp;
          buffer->setTransform(transform, "bag", is_static);
          if (!is_static) chain_stamps.push_back(transform.header.stamp.toSec());
        }
      } else if (auto odom = message.instantiate<nav_msgs::Odometry>()) {
        if (!options_.odom_topic.empty() && message.getTopic() == options_.odom_topic) {
          geometry_msgs::Transform t;
          t.translation.x = odom->pose.pose.position.x;
          t.translation.y = odom->pose.pose.position.y;
          t.rotation = odom->pose.pose.orientation;
          if (odometry_.Add(odom->header.stamp.toSec(), FromRosTransform(t)).ok()) {
            ++stats_.odometry_samples;
          }
        }
      } else if (auto scan = message.instantiate<sensor_msgs::LaserScan>()) {
        const double stamp = scan->header.stamp.toSec();
        if (stamp >= window_begin_s_ && stamp < window_end_s_) {
          laser_frames.insert(scan->header.frame_id);
          ++stats_.scans_in_window;
        }
      }
    }
  } catch (const std::exception& e) {
    return Status::Error(std::string("cannot read the bags: ") + e.what());
  }

  if (options_.odom_topic.empty()) {
    // Odometry samples at every stamp where a transform of the recording changed.
    std::sort(chain_stamps.begin(), chain_stamps.end());
    chain_stamps.erase(std::unique(chain_stamps.begin(), chain_stamps.end()), chain_stamps.end());
    for (double stamp : chain_stamps) {
      try {
        const auto t =
            buffer->lookupTransform(options_.odom_frame, options_.base_frame, ros::Time(stamp));
        if (odometry_.Add(stamp, FromRosTransform(t.transform)).ok()) ++stats_.odometry_samples;
      } catch (const tf2::TransformException&) {
        // This stamp belongs to a transform outside the odom -> base chain.
      }
    }
  }
  if (odometry_.empty()) {
    return Status::Error(options_.odom_topic.empty()
                             ? "no odometry: no transform " + options_.odom_frame + " -> " +
                                   options_.base_frame + " in /tf"
                             : "no odometry: no nav_msgs/Odometry on " + options_.odom_topic);
  }

  for (const std::string& frame : laser_frames) {
    Pose2 base_T_laser;
    if (frame == options_.base_frame) {
      laser_offsets_.emplace_back(frame, base_T_laser);
      continue;
    }
    try {
      const auto t = buffer->lookupTransform(options_.base_frame, frame, ros::Time(0));
      base_T_laser = FromRosTransform(t.transform);
    } catch (const tf2::TransformException& e) {
      stats_.laser_offset_found = false;
      warnings_.push_back("no transform " + options_.base_frame + " -> " + frame +
                          " in the bags; assuming the laser sits at the base origin");
    }
    laser_offsets_.emplace_back(frame, base_T_laser);
  }
  return Status::Ok();
}

Status BagScanSource::ForEach(const std::function<void(const ScanInput&)>& visit) {
  if (bags_ == nullptr) return Status::Error("the bags are not open");
  const TimeSpan span = ReadTimeSpan();

  // Scans are re-ordered by header stamp within a bounded window (bags are ordered by receive
  // time, which can differ from the stamp).
  using Pending = std::pair<double, ScanInput>;
  auto later = [](const Pending& a, const Pending& b) { return a.first > b.first; };
  std::priority_queue<Pending, std::vector<Pending>, decltype(later)> pending(later);
  double last_emitted = -std::numeric_limits<double>::infinity();
  auto emit = [&](const Pending& entry) {
    if (entry.first < last_emitted) ++stats_.scans_out_of_order;
    last_emitted = std::max(last_emitted, entry.first);
    if (stats_.scans_emitted == 0) stats_.first_stamp_s = entry.first;
    stats_.last_stamp_s = entry.first;
    ++stats_.scans_emitted;
    visit(entry.second);
  };

  try {
    rosbag::View view;
    for (auto& bag : bags_->bags) {
      view.addQuery(*bag, rosbag::TopicQuery(options_.scan_topic), span.begin, span.end);
    }
    for (const rosbag::MessageInstance& message : view) {
      auto msg = message.instantiate<sensor_msgs::LaserScan>();
      if (!msg) continue;
      ScanInput input;
      input.scan = FromRosScan(*msg);
      const double stamp = input.scan.stamp_s;
      if (!(stamp >= window_begin_s_ && stamp < window_end_s_)) continue;
      const auto odom_T_base = odometry_.Interpolate(stamp, options_.odometry_tolerance_s);
      if (!odom_T_base) {
        ++stats_.scans_without_odometry;
        continue;
      }
      input.odom_T_base = *odom_T_base;
      for (const auto& [frame, offset] : laser_offsets_) {
        if (frame == input.scan.frame_id) input.base_T_laser = offset;
      }
      pending.emplace(stamp, std::move(input));
      if (static_cast<int>(pending.size()) > options_.reorder_window) {
        emit(pending.top());
        pending.pop();
      }
    }
  } catch (const std::exception& e) {
    return Status::Error(std::string("cannot read the bags: ") + e.what());
  }
  while (!pending.empty()) {
    emit(pending.top());
    pending.pop();
  }
  return Status::Ok();
}

}  // namespace longterm_mapper2d_ros
