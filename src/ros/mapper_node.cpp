#include "longterm_mapper2d/ros/mapper_node.h"

#include <nav_msgs/MapMetaData.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "longterm_mapper2d/MapperStatus.h"
#include "longterm_mapper2d/core/io/atomic_file.h"
#include "longterm_mapper2d/core/map/session_map_file.h"
#include "longterm_mapper2d/ros/conversions.h"
#include "longterm_mapper2d/ros/ros_param_reader.h"

namespace longterm_mapper2d_ros {

using longterm_mapper2d::Pose2;
using longterm_mapper2d::ScanInput;
using longterm_mapper2d::Status;

MapperNode::MapperNode(ros::NodeHandle nh, ros::NodeHandle private_nh)
    : nh_(nh), private_nh_(private_nh) {}

MapperNode::~MapperNode() {
  stop_ = true;
  queue_cv_.notify_all();
  if (worker_.joinable()) worker_.join();
}

Status MapperNode::Start() {
  RosParamReader reader(private_nh_, "");
  LoadRosParams(private_nh_, "", node_options_, reader);
  LoadRosParams(private_nh_, "", mapper_options_, reader);
  if (Status s = reader.Finish(); !s.ok()) return s;
  requested_mode_ = node_options_.mode == "localization"
                        ? longterm_mapper2d::MapperMode::kLocalization
                        : longterm_mapper2d::MapperMode::kMapping;
  mapper_ = std::make_unique<longterm_mapper2d::Mapper>(mapper_options_);
  if (Status s = longterm_mapper2d::MakeDirectories(node_options_.map_folder); !s.ok()) {
    return Status::Error("map_folder: " + s.message());
  }
  if (!node_options_.load_map.empty()) {
    if (Status s = StartSessionOn(node_options_.load_map, std::nullopt); !s.ok()) return s;
  }

  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(tf_buffer_, nh_);
  const std::string target =
      node_options_.odom_topic.empty() ? node_options_.odom_frame : node_options_.base_frame;
  scan_subscriber_.subscribe(nh_, node_options_.scan_topic, 100);
  scan_filter_ = std::make_unique<tf2_ros::MessageFilter<sensor_msgs::LaserScan>>(
      scan_subscriber_, tf_buffer_, target, static_cast<uint32_t>(node_options_.scan_queue_size),
      nh_);
  scan_filter_->setTolerance(ros::Duration(0.0));
  scan_filter_->registerCallback([this](const sensor_msgs::LaserScan::ConstPtr& msg) { OnScan(msg); });
  scan_filter_->registerFailureCallback(
      [this](const sensor_msgs::LaserScan::ConstPtr& msg,
             tf2_ros::filter_failure_reasons::FilterFailureReason reason) {
        OnScanDropped(msg, reason);
      });
  if (!node_options_.odom_topic.empty()) {
    odometry_subscriber_ =
        nh_.subscribe(node_options_.odom_topic, 200, &MapperNode::OnOdometry, this);
  }
  initial_pose_subscriber_ = nh_.subscribe("initialpose", 1, &MapperNode::OnInitialPose, this);

  map_publisher_ = nh_.advertise<nav_msgs::OccupancyGrid>("map", 1, true);
  map_metadata_publisher_ = nh_.advertise<nav_msgs::MapMetaData>("map_metadata", 1, true);
  graph_publisher_ = private_nh_.advertise<visualization_msgs::MarkerArray>("graph", 1, true);
  local_map_publisher_ = private_nh_.advertise<sensor_msgs::PointCloud2>("local_map", 1);
  map_cloud_publisher_ = private_nh_.advertise<sensor_msgs::PointCloud2>("map_cloud", 1, true);
  trajectory_publisher_ = private_nh_.advertise<nav_msgs::Path>("trajectory", 1, true);
  status_publisher_ = private_nh_.advertise<longterm_mapper2d::MapperStatus>("status", 1, true);
  save_service_ = private_nh_.advertiseService("save_map", &MapperNode::OnSaveMap, this);
  load_service_ = private_nh_.advertiseService("load_map", &MapperNode::OnLoadMap, this);
  optimize_service_ = private_nh_.advertiseService("optimize", &MapperNode::OnOptimize, this);
  mode_service_ = private_nh_.advertiseService("set_mode", &MapperNode::OnSetMode, this);
  diagnostics_ = std::make_unique<diagnostic_updater::Updater>(nh_, private_nh_);
  diagnostics_->setHardwareID("none");
  diagnostics_->add("mapper", this, &MapperNode::Diagnose);
  diagnostics_timer_ = nh_.createTimer(ros::Duration(1.0),
                                       [this](const ros::TimerEvent&) { diagnostics_->update(); });

  worker_ = std::thread([this] { WorkerLoop(); });
  tf_timer_ = nh_.createTimer(ros::Duration(1.0 / node_options_.tf_publish_rate_hz),
                              &MapperNode::PublishTransform, this);
  map_timer_ = nh_.createTimer(ros::Duration(node_options_.map_update_interval_s),
                               &MapperNode::PublishMapAndGraph, this);
  ROS_INFO("longterm_mapper2d: mapping %s in %s (odometry %s -> %s%s)",
           nh_.resolveName(node_options_.scan_topic).c_str(), node_options_.map_frame.c_str(),
           node_options_.odom_frame.c_str(), node_options_.base_frame.c_str(),
           node_options_.odom_topic.empty() ? ", from TF" : ", from the odometry topic");
  return Status::Ok();
}

Status MapperNode::StartSessionOn(const std::string& path, const std::optional<Pose2>& pose) {
  auto map = longterm_mapper2d::LoadSessionMap(path);
  if (!map.ok()) return map.status();
  auto mapper = std::make_unique<longterm_mapper2d::Mapper>(mapper_options_);
  if (Status s = mapper->LoadSession(*map, pose); !s.ok()) return s;
  if (Status s = mapper->SetMode(requested_mode_); !s.ok()) return s;
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  mapper_ = std::move(mapper);
  loaded_map_ = std::move(*map);
  map_T_odom_ = Pose2();
  ROS_INFO("longterm_mapper2d: session %d starts on %s (%zu nodes)", mapper_->session_id(),
           path.c_str(), loaded_map_->nodes.size());
  return Status::Ok();
}

void MapperNode::OnScanDropped(const sensor_msgs::LaserScan::ConstPtr& msg,
                               tf2_ros::filter_failure_reasons::FilterFailureReason) {
  ++scans_dropped_no_tf_;
  ROS_WARN_THROTTLE(5.0, "longterm_mapper2d: scan at %.3f dropped: no odometry TF %s -> %s",
                    msg->header.stamp.toSec(), node_options_.odom_frame.c_str(),
                    msg->header.frame_id.c_str());
}

void MapperNode::OnOdometry(const nav_msgs::Odometry::ConstPtr& msg) {
  geometry_msgs::Transform t;
  t.translation.x = msg->pose.pose.position.x;
  t.translation.y = msg->pose.pose.position.y;
  t.rotation = msg->pose.pose.orientation;
  std::lock_guard<std::mutex> lock(odometry_mutex_);
  if (!odometry_.Add(msg->header.stamp.toSec(), FromRosTransform(t)).ok()) {
    ROS_WARN_THROTTLE(5.0, "longterm_mapper2d: odometry went back in time; restarting its buffer");
    odometry_.Clear();
    odometry_.Add(msg->header.stamp.toSec(), FromRosTransform(t));
  }
  odometry_.TrimBefore(msg->header.stamp.toSec() - 30.0);
}

void MapperNode::OnScan(const sensor_msgs::LaserScan::ConstPtr& msg) {
  try {
    ScanInput input;
    input.scan = FromRosScan(*msg);
    const ros::Time stamp = msg->header.stamp;
    if (input.scan.stamp_s < last_scan_stamp_s_) {
      ++scans_refused_time_backwards_;
      ROS_WARN_THROTTLE(5.0, "longterm_mapper2d: scan time went backwards (%.3f < %.3f): refused; "
                        "restart the node or load the map to start a new session",
                        input.scan.stamp_s, last_scan_stamp_s_);
      return;
    }
    if (node_options_.odom_topic.empty()) {
      input.odom_T_base = FromRosTransform(
          tf_buffer_.lookupTransform(node_options_.odom_frame, node_options_.base_frame, stamp)
              .transform);
    } else {
      std::lock_guard<std::mutex> lock(odometry_mutex_);
      const auto pose = odometry_.Interpolate(input.scan.stamp_s, 0.2);
      if (!pose) {
        ++scans_dropped_no_tf_;
        ROS_WARN_THROTTLE(5.0, "longterm_mapper2d: no odometry at %.3f; scan dropped",
                          input.scan.stamp_s);
        return;
      }
      input.odom_T_base = *pose;
    }
    input.base_T_laser = FromRosTransform(
        tf_buffer_.lookupTransform(node_options_.base_frame, msg->header.frame_id, stamp,
                                   ros::Duration(0.05))
            .transform);
    last_scan_stamp_s_ = input.scan.stamp_s;
    std::lock_guard<std::mutex> lock(queue_mutex_);
    if (static_cast<int>(queue_.size()) >= node_options_.scan_queue_size) {
      ++scans_dropped_queue_full_;
      ROS_WARN_THROTTLE(5.0, "longterm_mapper2d: mapping is behind; scan dropped");
      return;
    }
    queue_.push_back(std::move(input));
    queue_cv_.notify_one();
  } catch (const std::exception& e) {
    ++scans_dropped_no_tf_;
    ROS_WARN_THROTTLE(5.0, "longterm_mapper2d: scan dropped: %s", e.what());
  }
}

void MapperNode::OnInitialPose(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg) {
  geometry_msgs::Transform t;
  t.translation.x = msg->pose.pose.position.x;
  t.translation.y = msg->pose.pose.position.y;
  t.rotation = msg->pose.pose.orientation;
  const Pose2 pose = FromRosTransform(t);
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  if (!loaded_map_ || mapper_->stats().scans_received > 0) {
    ROS_WARN("longterm_mapper2d: initial pose ignored: it places the robot in a loaded map before "
             "the session's first scan (relocalising a running session is not supported)");
    return;
  }
  auto mapper = std::make_unique<longterm_mapper2d::Mapper>(mapper_options_);
  if (Status s = mapper->LoadSession(*loaded_map_, pose); !s.ok()) {
    ROS_WARN("longterm_mapper2d: initial pose ignored: %s", s.message().c_str());
    return;
  }
  mapper->SetMode(requested_mode_);  // the map is loaded, so this cannot fail
  mapper_ = std::move(mapper);
  ROS_INFO("longterm_mapper2d: the session starts at %s in the loaded map", pose.ToString().c_str());
}

void MapperNode::WorkerLoop() {
  while (!stop_) {
    ScanInput input;
    {
      std::unique_lock<std::mutex> lock(queue_mutex_);
      queue_cv_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      input = std::move(queue_.front());
      queue_.pop_front();
    }
    {
      // The mapper skips (and counts) a scan it cannot use; say why, now and then.
      // (A clockwise scan is turned round by the mapper, so only its turned copy is checked.)
      longterm_mapper2d::LaserScan turned;
      const longterm_mapper2d::LaserScan* check = &input.scan;
      if (input.scan.angle_increment_rad < 0.0) {
        turned = input.scan;
        turned.MakeCounterClockwise();
        check = &turned;
      }
      if (Status s = check->ValidateGeometry(); !s.ok()) {
        ROS_WARN_THROTTLE(5.0, "longterm_mapper2d: scan skipped: %s", s.message().c_str());
      }
    }
    try {
      std::lock_guard<std::mutex> lock(mapper_mutex_);
      mapper_->AddScan(input);
      last_scan_wall_time_ = ros::WallTime::now();
      map_T_odom_ = mapper_->map_T_odom();
    } catch (const std::exception& e) {
      ROS_ERROR_THROTTLE(5.0, "longterm_mapper2d: scan not mapped: %s", e.what());
    }
  }
}

}  // namespace longterm_mapper2d_ros
