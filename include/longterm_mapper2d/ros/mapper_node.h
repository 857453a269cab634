#pragma once

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <message_filters/subscriber.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Trigger.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "longterm_mapper2d/LoadMap.h"
#include "longterm_mapper2d/SaveMap.h"
#include "longterm_mapper2d/SetMode.h"
#include "longterm_mapper2d/core/config/mapper_options.h"
#include "longterm_mapper2d/core/mapping/mapper.h"
#include "longterm_mapper2d/core/sensor/odometry_buffer.h"
#include "longterm_mapper2d/ros/node_options.h"

namespace longterm_mapper2d_ros {

// The live mapper: scans (through a tf2 MessageFilter that waits for their odometry) go into a
// bounded queue; a worker thread feeds them to the core Mapper, so loop closing and optimisation
// never block the callbacks. Timers publish map -> odom, the occupancy grid, the graph markers,
// the clouds, the trajectory and the status; services save and load session maps.
class MapperNode {
 public:
  MapperNode(ros::NodeHandle nh, ros::NodeHandle private_nh);
  ~MapperNode();
  // Reads and checks the parameters (an unknown or invalid one refuses the start, named), loads
  // the start-up map if any, and starts subscribers, timers, services and the worker.
  longterm_mapper2d::Status Start();

  // Starts a new session on top of a saved map (the start-up map and ~load_map).
  longterm_mapper2d::Status StartSessionOn(const std::string& path,
                                           const std::optional<longterm_mapper2d::Pose2>& pose);

 private:
  void OnScan(const sensor_msgs::LaserScan::ConstPtr& msg);
  void OnScanDropped(const sensor_msgs::LaserScan::ConstPtr& msg,
                     tf2_ros::filter_failure_reasons::FilterFailureReason reason);
  void OnOdometry(const nav_msgs::Odometry::ConstPtr& msg);
  void OnInitialPose(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg);
  void WorkerLoop();

  // Publishing (mapper_node_outputs.cpp).
  void PublishTransform(const ros::TimerEvent& event);
  void PublishMapAndGraph(const ros::TimerEvent& event);
  bool OnSaveMap(longterm_mapper2d::SaveMap::Request& request,
                 longterm_mapper2d::SaveMap::Response& response);
  bool OnLoadMap(longterm_mapper2d::LoadMap::Request& request,
                 longterm_mapper2d::LoadMap::Response& response);
  bool OnOptimize(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool OnSetMode(longterm_mapper2d::SetMode::Request& request,
                 longterm_mapper2d::SetMode::Response& response);
  // /diagnostics (mapper_node_diagnostics.cpp).
  void Diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);
  // A service path inside the map folder; absolute paths are taken as they are, ".." is refused.
  longterm_mapper2d::StatusOr<std::string> ResolvePath(const std::string& path) const;

  ros::NodeHandle nh_;
  ros::NodeHandle private_nh_;
  NodeOptions node_options_;
  longterm_mapper2d::MapperOptions mapper_options_;

  std::mutex mapper_mutex_;  // guards mapper_ and the fields published from it
  std::unique_ptr<longterm_mapper2d::Mapper> mapper_;
  longterm_mapper2d::Pose2 map_T_odom_;
  // The map this session was started on, kept so that an rviz "2D Pose Estimate" given before the
  // first scan can restart the session at that pose.
  std::optional<longterm_mapper2d::SessionMap> loaded_map_;

  std::mutex queue_mutex_;
  std::condition_variable queue_cv_;
  std::deque<longterm_mapper2d::ScanInput> queue_;
  std::atomic<bool> stop_{false};
  std::thread worker_;

  std::mutex odometry_mutex_;
  longterm_mapper2d::OdometryBuffer odometry_;  // when odom_topic is set

  std::atomic<std::uint64_t> scans_dropped_no_tf_{0};
  std::atomic<std::uint64_t> scans_dropped_queue_full_{0};
  std::atomic<std::uint64_t> scans_refused_time_backwards_{0};
  double last_scan_stamp_s_ = -1.0;

  tf2_ros::Buffer tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  message_filters::Subscriber<sensor_msgs::LaserScan> scan_subscriber_;
  std::unique_ptr<tf2_ros::MessageFilter<sensor_msgs::LaserScan>> scan_filter_;
  ros::Subscriber odometry_subscriber_;
  ros::Subscriber initial_pose_subscriber_;
  ros::Publisher map_publisher_, map_metadata_publisher_, graph_publisher_, local_map_publisher_,
      map_cloud_publisher_, trajectory_publisher_, status_publisher_;
  ros::ServiceServer save_service_, load_service_, optimize_service_, mode_service_;
  ros::Timer tf_timer_, map_timer_, diagnostics_timer_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  // The mode the user asked for; a map loaded later starts in it too.
  longterm_mapper2d::MapperMode requested_mode_ = longterm_mapper2d::MapperMode::kMapping;
  // For /diagnostics: what changed since the last report.
  ros::WallTime last_scan_wall_time_;
  std::uint64_t diagnosed_dropped_ = 0, diagnosed_tracker_failures_ = 0;
  ros::Time last_tf_stamp_;
};

}  // namespace longterm_mapper2d_ros
