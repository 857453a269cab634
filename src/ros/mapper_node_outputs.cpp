// MapperNode: what it publishes and the services it offers.
#include <nav_msgs/MapMetaData.h>
#include <nav_msgs/Path.h>
#include <visualization_msgs/MarkerArray.h>

#include "longterm_mapper2d/MapperStatus.h"
#include "longterm_mapper2d/core/io/map_image_io.h"
#include "longterm_mapper2d/core/map/grid_renderer.h"
#include "longterm_mapper2d/core/map/session_map_file.h"
#include "longterm_mapper2d/ros/conversions.h"
#include "longterm_mapper2d/ros/mapper_node.h"

namespace longterm_mapper2d_ros {

using longterm_mapper2d::EdgeKind;
using longterm_mapper2d::Pose2;
using longterm_mapper2d::Status;

namespace {

std_msgs::ColorRGBA Color(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

geometry_msgs::Point Point(const Eigen::Vector2d& p) {
  geometry_msgs::Point point;
  point.x = p.x();
  point.y = p.y();
  return point;
}

// Nodes as spheres coloured by session; edges as lines coloured by kind (odometry grey, loop
// closure green, condensed blue).
visualization_msgs::MarkerArray GraphMarkers(const longterm_mapper2d::PoseGraph& graph,
                                             const std::string& frame, const ros::Time& stamp) {
  visualization_msgs::MarkerArray markers;
  visualization_msgs::Marker nodes;
  nodes.header.frame_id = frame;
  nodes.header.stamp = stamp;
  nodes.ns = "nodes";
  nodes.type = visualization_msgs::Marker::SPHERE_LIST;
  nodes.scale.x = nodes.scale.y = nodes.scale.z = 0.15;
  nodes.pose.orientation.w = 1.0;
  static const std_msgs::ColorRGBA kSessionColors[] = {Color(1, 0.6, 0), Color(0, 0.6, 1),
                                                       Color(0.8, 0, 0.8), Color(0.9, 0.9, 0)};
  for (const auto& [id, node] : graph.nodes()) {
    nodes.points.push_back(Point(node.pose.translation()));
    nodes.colors.push_back(kSessionColors[node.session_id % 4]);
  }
  markers.markers.push_back(nodes);
  const char* kinds[] = {"odometry_edges", "loop_closure_edges", "condensed_edges"};
  const std_msgs::ColorRGBA colors[] = {Color(0.6, 0.6, 0.6, 0.8), Color(0, 0.9, 0.2, 0.8),
                                        Color(0.2, 0.4, 1, 0.8)};
  for (int k = 0; k < 3; ++k) {
    visualization_msgs::Marker lines;
    lines.header = nodes.header;
    lines.ns = kinds[k];
    lines.type = visualization_msgs::Marker::LINE_LIST;
    lines.scale.x = 0.03;
    lines.color = colors[k];
    lines.pose.orientation.w = 1.0;
    for (const auto& edge : graph.edges()) {
      if (static_cast<int>(edge.kind) != k) continue;
      lines.points.push_back(Point(graph.node(edge.from).pose.translation()));
      lines.points.push_back(Point(graph.node(edge.to).pose.translation()));
    }
    markers.markers.push_back(lines);
  }
  return markers;
}

}  // namespace

void MapperNode::PublishTransform(const ros::TimerEvent&) {
  Pose2 map_T_odom;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    map_T_odom = map_T_odom_;
  }
  geometry_msgs::TransformStamped t;
  // Future-dated so that lookups at the latest scan stamp succeed (REP-105). Under simulated time
  // the clock may not have moved since the last call: a repeated stamp is not sent again.
  t.header.stamp = ros::Time::now() + ros::Duration(node_options_.transform_tolerance_s);
  if (t.header.stamp <= last_tf_stamp_) return;
  last_tf_stamp_ = t.header.stamp;
  t.header.frame_id = node_options_.map_frame;
  t.child_frame_id = node_options_.odom_frame;
  t.transform = ToRosTransform(map_T_odom);
  tf_broadcaster_.sendTransform(t);
}

void MapperNode::PublishMapAndGraph(const ros::WallTimerEvent&) {
  std::vector<longterm_mapper2d::PosedScan> scans;
  longterm_mapper2d::PoseGraph graph;
  longterm_mapper2d::Cloud map_cloud, local_map;
  std::vector<longterm_mapper2d::StampedPose2> trajectory;
  longterm_mapper2d::MapperStatus status;
  {
    // Copy under the lock, render outside it: the worker keeps mapping meanwhile.
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    scans = mapper_->WaypointScans();
    graph = mapper_->graph();
    trajectory = mapper_->Trajectory();
    local_map = mapper_->LocalMapInMap();
    for (const auto& [id, node] : mapper_->nodes()) {
      const auto placed = longterm_mapper2d::Transform(node.map_T_node, node.cloud);
      map_cloud.insert(map_cloud.end(), placed.begin(), placed.end());
    }
    const auto& stats = mapper_->stats();
    auto counter = [&stats](const char* name) -> std::uint64_t {
      const auto it = stats.counters.find(name);
      return it == stats.counters.end() ? 0 : it->second;
    };
    status.session_id = mapper_->session_id();
    status.mode = longterm_mapper2d::MapperModeName(mapper_->mode());
    status.merges = counter("merges");
    status.nodes_removed = counter("nodes_removed");
    status.scans_received = stats.scans_received;
    status.scans_processed = stats.scans_processed;
    status.scans_skipped = stats.TotalSkipped() + scans_refused_time_backwards_;
    status.tracker_failures = counter("tracker_failures");
    status.loop_closures_accepted = counter("loop_closures_accepted");
    const auto optimization = stats.stage_times.seconds().find("optimization");
    status.last_optimization_time_s =
        optimization == stats.stage_times.seconds().end() ? 0.0 : optimization->second;
  }
  status.scans_dropped_no_tf = scans_dropped_no_tf_ + scans_dropped_queue_full_;
  status.nodes = graph.nodes().size();
  for (const auto& edge : graph.edges()) {
    if (edge.kind == EdgeKind::kOdometry) ++status.edges_odometry;
    if (edge.kind == EdgeKind::kLoopClosure) ++status.edges_loop_closure;
    if (edge.kind == EdgeKind::kCondensed) ++status.edges_condensed;
  }
  const ros::Time now = ros::Time::now();
  status.header.stamp = now;
  status_publisher_.publish(status);
  const std::string& frame = node_options_.map_frame;
  if (!scans.empty()) {
    auto grid = longterm_mapper2d::RenderOccupancyGrid(scans, mapper_options_.grid);
    if (grid.ok()) {
      const nav_msgs::OccupancyGrid msg = ToRosGrid(*grid, frame, now);
      map_publisher_.publish(msg);
      map_metadata_publisher_.publish(msg.info);
    } else {
      ROS_WARN_THROTTLE(30.0, "longterm_mapper2d: map not rendered: %s",
                        grid.status().message().c_str());
    }
  }
  graph_publisher_.publish(GraphMarkers(graph, frame, now));
  map_cloud_publisher_.publish(ToRosCloud(map_cloud, frame, now));
  local_map_publisher_.publish(ToRosCloud(local_map, frame, now));
  nav_msgs::Path path;
  path.header.frame_id = frame;
  path.header.stamp = now;
  for (const auto& entry : trajectory) {
    geometry_msgs::PoseStamped pose;
    pose.header.frame_id = frame;
    pose.header.stamp = ros::Time(entry.stamp_s);
    const auto t = ToRosTransform(entry.pose);
    pose.pose.position.x = t.translation.x;
    pose.pose.position.y = t.translation.y;
    pose.pose.orientation = t.rotation;
    path.poses.push_back(pose);
  }
  trajectory_publisher_.publish(path);
}

longterm_mapper2d::StatusOr<std::string> MapperNode::ResolvePath(const std::string& path) const {
  if (path.empty()) return Status::Error("empty path");
  if (path == ".." || path.rfind("../", 0) == 0 || path.find("/../") != std::string::npos ||
      (path.size() >= 3 && path.compare(path.size() - 3, 3, "/..") == 0)) {
    return Status::Error("path '" + path + "' escapes with '..'; refused");
  }
  if (path[0] == '/') return path;
  return node_options_.map_folder + "/" + path;
}

bool MapperNode::OnSaveMap(longterm_mapper2d::SaveMap::Request& request,
                           longterm_mapper2d::SaveMap::Response& response) {
  auto resolved = ResolvePath(request.path);
  if (!resolved.ok()) {
    response.success = false;
    response.message = resolved.status().message();
    return true;
  }
  std::string base = *resolved;
  if (base.size() > 6 && base.compare(base.size() - 6, 6, ".ltmap") == 0) {
    base.resize(base.size() - 6);
  }
  longterm_mapper2d::SessionMap session;
  std::vector<longterm_mapper2d::PosedScan> scans;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    session = mapper_->ExportSession();
    scans = mapper_->WaypointScans();
  }
  if (session.nodes.empty()) {
    response.success = false;
    response.message = "nothing to save yet: the map has no node";
    return true;
  }
  if (Status s = longterm_mapper2d::SaveSessionMap(session, base + ".ltmap"); !s.ok()) {
    response.success = false;
    response.message = s.message();
    return true;
  }
  auto grid = longterm_mapper2d::RenderOccupancyGrid(scans, mapper_options_.grid);
  Status s = grid.ok() ? longterm_mapper2d::WriteMapPgmYaml(*grid, base + ".yaml") : grid.status();
  response.success = s.ok();
  response.message = s.ok() ? "saved " + base + ".ltmap, " + base + ".pgm and " + base + ".yaml"
                            : "saved " + base + ".ltmap, but not the grid: " + s.message();
  ROS_INFO("longterm_mapper2d: %s", response.message.c_str());
  return true;
}

bool MapperNode::OnLoadMap(longterm_mapper2d::LoadMap::Request& request,
                           longterm_mapper2d::LoadMap::Response& response) {
  auto resolved = ResolvePath(request.path);
  std::optional<Pose2> pose;
  if (request.use_initial_pose) {
    pose = Pose2(request.initial_pose.x, request.initial_pose.y, request.initial_pose.theta);
  }
  const Status s = resolved.ok() ? StartSessionOn(*resolved, pose) : resolved.status();
  if (s.ok()) {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    queue_.clear();
  }
  response.success = s.ok();
  response.message = s.ok() ? "a new session starts on " + *resolved : s.message();
  return true;
}

bool MapperNode::OnOptimize(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  const Status s = mapper_->OptimizeNow();
  response.success = s.ok();
  response.message = s.ok() ? "optimised" : s.message();
  return true;
}

bool MapperNode::OnSetMode(longterm_mapper2d::SetMode::Request& request,
                           longterm_mapper2d::SetMode::Response& response) {
  longterm_mapper2d::MapperMode mode;
  if (request.mode == "mapping") {
    mode = longterm_mapper2d::MapperMode::kMapping;
  } else if (request.mode == "localization") {
    mode = longterm_mapper2d::MapperMode::kLocalization;
  } else {
    response.success = false;
    response.message = "unknown mode '" + request.mode + "' (mapping or localization)";
    return true;
  }
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  const Status s = mapper_->SetMode(mode);
  response.success = s.ok();
  if (s.ok()) {
    requested_mode_ = mode;
    response.message = std::string("mode: ") + longterm_mapper2d::MapperModeName(mode);
    ROS_INFO("longterm_mapper2d: %s", response.message.c_str());
  } else {
    response.message = s.message();
  }
  return true;
}

}  // namespace longterm_mapper2d_ros
