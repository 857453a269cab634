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
  if (scan_spinner_) scan_spinner_->stop();
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

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>(ros::Duration(node_options_.tf_cache_s));
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh_);
  scan_nh_ = nh_;
  scan_nh_.setCallbackQueue(&scan_callback_queue_);
  // The subscriber's own queue holds what arrives while the scan thread is busy; a scan it
  // overflows is lost uncounted, so it is as deep as the node's counted queues.
  scan_subscriber_ = scan_nh_.subscribe(node_options_.scan_topic, node_options_.scan_queue_size,
                                        &MapperNode::OnScan, this);
  // A scan still waiting for its odometry when no newer scan comes is retried by this timer.
  odometry_retry_timer_ = scan_nh_.createWallTimer(
      ros::WallDuration(0.05), [this](const ros::WallTimerEvent&) { MapWaitingScans(); });
  if (!node_options_.odom_topic.empty()) {
    odometry_subscriber_ =
        scan_nh_.subscribe(node_options_.odom_topic, 200, &MapperNode::OnOdometry, this);
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
  diagnostics_timer_ = nh_.createWallTimer(
      ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { diagnostics_->update(); });

  worker_ = std::thread([this] { WorkerLoop(); });
  scan_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &scan_callback_queue_);
  scan_spinner_->start();
  tf_timer_ = nh_.createTimer(ros::Duration(1.0 / node_options_.tf_publish_rate_hz),
                              &MapperNode::PublishTransform, this);
  map_timer_ = nh_.createWallTimer(ros::WallDuration(node_options_.map_update_interval_s),
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

void MapperNode::OnInitialPose(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg) {
  geometry_msgs::Transform t;
  t.translation.x = msg->pose.pose.position.x;
  t.translation.y = msg->pose.pose.position.y;
  t.rotation = msg->pose.pose.orientation;
  const Pose2 pose = FromRosTransform(t);
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  if (!loaded_map_ || mapper_->stats().scans_received > 0) {
    ROS_WARN(
        "longterm_mapper2d: initial pose ignored: it places the robot in a loaded map before "
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
  ROS_INFO("longterm_mapper2d: the session starts at %s in the loaded map",
           pose.ToString().c_str());
}

void MapperNode::WorkerLoop() {
  while (!stop_) {
    QueuedScan queued;
    {
      std::unique_lock<std::mutex> lock(queue_mutex_);
      queue_cv_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      queued = std::move(queue_.front());
      queue_.pop_front();
    }
    const ScanInput& input = queued.input;
    if (queued.new_session) {
      std::lock_guard<std::mutex> lock(mapper_mutex_);
      StartNewSessionOnCurrentMap();
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

void MapperNode::StartNewSessionOnCurrentMap() {
  mapper_->Finish();
  longterm_mapper2d::SessionMap map = mapper_->ExportSession();
  auto mapper = std::make_unique<longterm_mapper2d::Mapper>(mapper_options_);
  if (!map.nodes.empty()) {
    // The map was made by this mapper and is consistent, so loading it cannot fail; if it did,
    // mapping goes on in the old session rather than losing the map.
    if (Status s = mapper->LoadSession(map, std::nullopt); !s.ok()) {
      ROS_ERROR("longterm_mapper2d: no new session: %s", s.message().c_str());
      return;
    }
    loaded_map_ = std::move(map);
  }
  mapper->SetMode(loaded_map_ ? requested_mode_ : longterm_mapper2d::MapperMode::kMapping);
  mapper_ = std::move(mapper);
  map_T_odom_ = mapper_->map_T_odom();
  ++sessions_started_time_backwards_;
  ROS_INFO("longterm_mapper2d: session %d starts on the map of the previous one (%zu nodes)",
           mapper_->session_id(), loaded_map_ ? loaded_map_->nodes.size() : std::size_t{0});
}

}  // namespace longterm_mapper2d_ros
