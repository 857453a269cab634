#pragma once

#include <string>

#include "longterm_mapper2d/core/config/option_errors.h"

namespace longterm_mapper2d_ros {

// What the node adds to the mapper's options: topics, frames, rates, where maps are saved.
struct NodeOptions {
  std::string scan_topic = "scan";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  std::string map_frame = "map";
  // If set, odometry comes from this nav_msgs/Odometry topic instead of TF.
  std::string odom_topic;
  double tf_publish_rate_hz = 20.0;
  // map -> odom is stamped this far in the future (REP-105: it must cover the lookup delay).
  double transform_tolerance_s = 0.1;
  // Grid, graph, clouds, trajectory and status are republished every this many wall-clock
  // seconds (whatever the play rate of a bag).
  double map_update_interval_s = 2.0;
  // Scans waiting for their odometry, and scans waiting for the worker; beyond this the oldest
  // waiting for odometry (or the newest for the worker) is dropped and counted.
  int scan_queue_size = 200;
  // A scan waits for the odometry at its stamp until a scan this much newer (in stamp time) has
  // arrived; then it is dropped and counted. (The Radish logs have odometry gaps of up to 3 s.)
  double odometry_wait_s = 5.0;
  // TF history kept (stamp time). A scan is looked up at its stamp when the scan thread comes to
  // it, which under load (or a bag played fast) can be well after the stamp: a short history
  // would drop scans whose transforms have already been forgotten. Must exceed odometry_wait_s.
  double tf_cache_s = 60.0;
  // Relative service paths are resolved here; paths escaping it with ".." are refused.
  std::string map_folder = "maps";
  // A session map to continue at start-up ("" for a new map).
  std::string load_map;
  // "mapping" or "localization" (needs load_map); ~set_mode switches later.
  std::string mode = "mapping";
  // /diagnostics: the scan input is stale after this long without a scan.
  double diagnostics_scan_timeout_s = 5.0;
  // A scan older than the last one (a looped bag, a restarted driver): "refuse" drops it (and
  // every scan until time passes the last stamp again); "new_session" ends the session and starts
  // a new one on the map built so far, the robot at the map's origin (a looped bag's robot is
  // back at its start).
  std::string time_backwards = "refuse";

  template <class V>
  void Visit(V& v) {
    v("scan_topic", scan_topic);
    v("odom_frame", odom_frame);
    v("base_frame", base_frame);
    v("map_frame", map_frame);
    v("odom_topic", odom_topic);
    v("tf_publish_rate_hz", tf_publish_rate_hz);
    v("transform_tolerance_s", transform_tolerance_s);
    v("map_update_interval_s", map_update_interval_s);
    v("scan_queue_size", scan_queue_size);
    v("odometry_wait_s", odometry_wait_s);
    v("tf_cache_s", tf_cache_s);
    v("map_folder", map_folder);
    v("load_map", load_map);
    v("mode", mode);
    v("diagnostics_scan_timeout_s", diagnostics_scan_timeout_s);
    v("time_backwards", time_backwards);
  }
  void Validate(longterm_mapper2d::OptionErrors& e) const {
    e.Require(!scan_topic.empty(), "scan_topic", "must not be empty");
    e.Require(!odom_frame.empty() && !base_frame.empty() && !map_frame.empty(), "map_frame",
              "frames must not be empty");
    e.Require(odom_frame != map_frame, "map_frame", "must differ from odom_frame");
    e.Require(tf_publish_rate_hz > 0.0, "tf_publish_rate_hz", "must be positive");
    e.Require(transform_tolerance_s >= 0.0, "transform_tolerance_s", "must be non-negative");
    e.Require(map_update_interval_s > 0.0, "map_update_interval_s", "must be positive");
    e.Require(scan_queue_size >= 1, "scan_queue_size", "must be at least 1");
    e.Require(odometry_wait_s > 0.0, "odometry_wait_s", "must be positive");
    e.Require(tf_cache_s > odometry_wait_s, "tf_cache_s", "must exceed odometry_wait_s");
    e.Require(!map_folder.empty(), "map_folder", "must not be empty");
    e.Require(mode == "mapping" || mode == "localization", "mode",
              "must be 'mapping' or 'localization'");
    e.Require(mode == "mapping" || !load_map.empty(), "mode", "localization needs load_map");
    e.Require(diagnostics_scan_timeout_s > 0.0, "diagnostics_scan_timeout_s", "must be positive");
    e.Require(time_backwards == "refuse" || time_backwards == "new_session", "time_backwards",
              "must be 'refuse' or 'new_session'");
  }
};

}  // namespace longterm_mapper2d_ros
