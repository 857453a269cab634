#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
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
  // Scan intake (mapper_node_input.cpp). Scans wait, in their order of arrival, until the
  // odometry at their stamp is known; one that waits longer than odometry_wait_s (in scan time)
  // is dropped and counted. Stamps going backwards follow the time_backwards option.
  void OnScan(const sensor_msgs::LaserScan::ConstPtr& msg);
  void OnOdometry(const nav_msgs::Odometry::ConstPtr& msg);
  // Hands every waiting scan whose odometry is known to the worker, in order (called for each
  // new scan or odometry message, and by a retry timer).
  void MapWaitingScans();
  // The scan with its odometry and laser mounting, if both are known at its stamp yet.
  std::optional<longterm_mapper2d::ScanInput> WithOdometry(const sensor_msgs::LaserScan& msg);
  // False if the worker's queue is full (the scan is dropped and counted).
  bool EnqueueForWorker(longterm_mapper2d::ScanInput input, bool new_session);
  void OnInitialPose(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg);
  void WorkerLoop();
  // Ends the session and starts the next one on its map, the robot at the map's origin
  // (mapper_mutex_ held).
  void StartNewSessionOnCurrentMap();

  // Publishing (mapper_node_outputs.cpp).
  void PublishTransform(const ros::TimerEvent& event);
  void PublishMapAndGraph(const ros::WallTimerEvent& event);
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
  // A scan for the worker; new_session: its stamp went back (time_backwards: new_session), so the
  // session ends before it and a new one starts on the map built so far.
  struct QueuedScan {
    longterm_mapper2d::ScanInput input;
    bool new_session = false;
  };
  std::deque<QueuedScan> queue_;
  std::atomic<bool> stop_{false};
  std::thread worker_;

  std::mutex odometry_mutex_;
  longterm_mapper2d::OdometryBuffer odometry_;  // when odom_topic is set

  std::atomic<std::uint64_t> scans_dropped_no_tf_{0};
  std::atomic<std::uint64_t> scans_dropped_queue_full_{0};
  std::atomic<std::uint64_t> scans_refused_time_backwards_{0};
  std::atomic<std::uint64_t> sessions_started_time_backwards_{0};

  // Scans and odometry have their own callback queue, served by one thread, so that scans are
  // taken in their order of arrival (the node's other spinner has several threads).
  ros::CallbackQueue scan_callback_queue_;
  ros::NodeHandle scan_nh_;
  std::unique_ptr<ros::AsyncSpinner> scan_spinner_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;  // made in Start() with tf_cache_s of history
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  ros::Subscriber scan_subscriber_;
  ros::WallTimer odometry_retry_timer_;
  // Scans waiting for their odometry (touched by the scan callback queue's thread only).
  std::deque<sensor_msgs::LaserScan::ConstPtr> waiting_for_odometry_;
  double newest_scan_stamp_s_ = -1.0;
  // Time went backwards (time_backwards: new_session): the next scan for the worker starts the
  // new session.
  bool new_session_pending_ = false;
  ros::Subscriber odometry_subscriber_;
  ros::Subscriber initial_pose_subscriber_;
  ros::Publisher map_publisher_, map_metadata_publisher_, graph_publisher_, local_map_publisher_,
      map_cloud_publisher_, trajectory_publisher_, status_publisher_;
  ros::ServiceServer save_service_, load_service_, optimize_service_, mode_service_;
  ros::Timer tf_timer_;
  // Wall-clock timers: rendering costs wall time whatever the play rate of a bag, and the outputs
  // keep coming after a bag's clock has stopped.
  ros::WallTimer map_timer_, diagnostics_timer_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  // The mode the user asked for; a map loaded later starts in it too.
  longterm_mapper2d::MapperMode requested_mode_ = longterm_mapper2d::MapperMode::kMapping;
  // For /diagnostics: what changed since the last report.
  ros::WallTime last_scan_wall_time_;
  std::uint64_t diagnosed_dropped_ = 0, diagnosed_tracker_failures_ = 0;
  ros::Time last_tf_stamp_;
};

}  // namespace longterm_mapper2d_ros
