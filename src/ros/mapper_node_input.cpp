// Scan intake of mapper_node: scans wait in their order of arrival for the odometry at their
// stamp, then go to the worker. (tf2_ros::MessageFilter is not used: it releases a scan as soon
// as its own transform is known, so two scans a few milliseconds apart can overtake each other,
// and the mapper needs them in order.)
#include <stdexcept>

#include "longterm_mapper2d/ros/conversions.h"
#include "longterm_mapper2d/ros/mapper_node.h"

namespace longterm_mapper2d_ros {

using longterm_mapper2d::ScanInput;

void MapperNode::OnOdometry(const nav_msgs::Odometry::ConstPtr& msg) {
  geometry_msgs::Transform t;
  t.translation.x = msg->pose.pose.position.x;
  t.translation.y = msg->pose.pose.position.y;
  t.rotation = msg->pose.pose.orientation;
  {
    std::lock_guard<std::mutex> lock(odometry_mutex_);
    if (!odometry_.Add(msg->header.stamp.toSec(), FromRosTransform(t)).ok()) {
      ROS_WARN_THROTTLE(5.0,
                        "longterm_mapper2d: odometry went back in time; restarting its buffer");
      odometry_.Clear();
      odometry_.Add(msg->header.stamp.toSec(), FromRosTransform(t));
    }
    odometry_.TrimBefore(msg->header.stamp.toSec() - 30.0);
  }
  MapWaitingScans();
}

void MapperNode::OnScan(const sensor_msgs::LaserScan::ConstPtr& msg) {
  const double stamp_s = msg->header.stamp.toSec();
  if (stamp_s < newest_scan_stamp_s_) {
    if (node_options_.time_backwards != "new_session") {
      ++scans_refused_time_backwards_;
      ROS_WARN_THROTTLE(5.0,
                        "longterm_mapper2d: scan time went backwards (%.3f < %.3f): "
                        "refused; restart the node, load the map to start a new session, or "
                        "set time_backwards: new_session",
                        stamp_s, newest_scan_stamp_s_);
      return;
    }
    ROS_WARN(
        "longterm_mapper2d: scan time went backwards (%.3f < %.3f): this session ends and "
        "a new one starts on its map, the robot at the map's origin",
        stamp_s, newest_scan_stamp_s_);
    // Scans of the old time still waiting will not get their odometry any more.
    scans_dropped_no_tf_ += waiting_for_odometry_.size();
    waiting_for_odometry_.clear();
    new_session_pending_ = true;
  }
  newest_scan_stamp_s_ = stamp_s;
  waiting_for_odometry_.push_back(msg);
  if (static_cast<int>(waiting_for_odometry_.size()) > node_options_.scan_queue_size) {
    ++scans_dropped_no_tf_;
    ROS_WARN_THROTTLE(5.0, "longterm_mapper2d: %zu scans wait for odometry; the oldest dropped",
                      waiting_for_odometry_.size());
    waiting_for_odometry_.pop_front();
  }
  MapWaitingScans();
}

void MapperNode::MapWaitingScans() {
  while (!waiting_for_odometry_.empty()) {
    const sensor_msgs::LaserScan& msg = *waiting_for_odometry_.front();
    std::optional<ScanInput> input;
    try {
      input = WithOdometry(msg);
    } catch (const std::exception& e) {
      ++scans_dropped_no_tf_;
      ROS_WARN_THROTTLE(5.0, "longterm_mapper2d: scan at %.3f dropped: %s",
                        msg.header.stamp.toSec(), e.what());
      waiting_for_odometry_.pop_front();
      continue;
    }
    if (!input) {
      if (newest_scan_stamp_s_ - msg.header.stamp.toSec() <= node_options_.odometry_wait_s) return;
      ++scans_dropped_no_tf_;
      ROS_WARN_THROTTLE(5.0,
                        "longterm_mapper2d: scan at %.3f dropped: no transform %s -> %s -> %s "
                        "at its stamp after %.1f s of newer scans",
                        msg.header.stamp.toSec(), node_options_.odom_frame.c_str(),
                        node_options_.base_frame.c_str(), msg.header.frame_id.c_str(),
                        node_options_.odometry_wait_s);
      waiting_for_odometry_.pop_front();
      continue;
    }
    if (EnqueueForWorker(std::move(*input), new_session_pending_)) new_session_pending_ = false;
    waiting_for_odometry_.pop_front();
  }
}

std::optional<ScanInput> MapperNode::WithOdometry(const sensor_msgs::LaserScan& msg) {
  const ros::Time stamp = msg.header.stamp;
  const double stamp_s = stamp.toSec();
  if (msg.header.frame_id.empty()) throw std::runtime_error("the scan has no frame_id");
  if (!tf_buffer_->canTransform(node_options_.base_frame, msg.header.frame_id, stamp)) {
    return std::nullopt;
  }
  ScanInput input;
  if (node_options_.odom_topic.empty()) {
    if (!tf_buffer_->canTransform(node_options_.odom_frame, node_options_.base_frame, stamp)) {
      return std::nullopt;
    }
    input.odom_T_base = FromRosTransform(
        tf_buffer_->lookupTransform(node_options_.odom_frame, node_options_.base_frame, stamp)
            .transform);
  } else {
    std::lock_guard<std::mutex> lock(odometry_mutex_);
    if (odometry_.empty() || odometry_.back_stamp_s() < stamp_s) return std::nullopt;
    const auto pose = odometry_.Interpolate(stamp_s, 0.2);
    if (!pose) throw std::runtime_error("no odometry message within 0.2 s of its stamp");
    input.odom_T_base = *pose;
  }
  input.base_T_laser = FromRosTransform(
      tf_buffer_->lookupTransform(node_options_.base_frame, msg.header.frame_id, stamp).transform);
  input.scan = FromRosScan(msg);
  return input;
}

bool MapperNode::EnqueueForWorker(ScanInput input, bool new_session) {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  if (static_cast<int>(queue_.size()) >= node_options_.scan_queue_size) {
    ++scans_dropped_queue_full_;
    ROS_WARN_THROTTLE(5.0, "longterm_mapper2d: mapping is behind; scan dropped");
    return false;
  }
  queue_.push_back(QueuedScan{std::move(input), new_session});
  queue_cv_.notify_one();
  return true;
}

}  // namespace longterm_mapper2d_ros
