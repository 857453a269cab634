// /diagnostics of mapper_node: one status, "mapper", with the counters a robot operator needs.
#include <diagnostic_msgs/DiagnosticStatus.h>

#include "longterm_mapper2d/ros/mapper_node.h"

namespace longterm_mapper2d_ros {

void MapperNode::Diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  using diagnostic_msgs::DiagnosticStatus;
  std::uint64_t received = 0, processed = 0, skipped = 0, tracker_failures = 0, nodes = 0;
  std::uint64_t closures = 0, merges = 0;
  std::string mode;
  int session = 0;
  ros::WallTime last_scan;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    const auto& stats = mapper_->stats();
    auto counter = [&stats](const char* name) -> std::uint64_t {
      const auto it = stats.counters.find(name);
      return it == stats.counters.end() ? 0 : it->second;
    };
    received = stats.scans_received;
    processed = stats.scans_processed;
    skipped = stats.TotalSkipped();
    tracker_failures = counter("tracker_failures");
    closures = counter("loop_closures_accepted");
    merges = counter("merges");
    nodes = mapper_->nodes().size();
    mode = longterm_mapper2d::MapperModeName(mapper_->mode());
    session = mapper_->session_id();
    last_scan = last_scan_wall_time_;
  }
  std::size_t queued = 0;
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    queued = queue_.size();
  }
  const std::uint64_t dropped =
      scans_dropped_no_tf_ + scans_dropped_queue_full_ + scans_refused_time_backwards_;

  // The worst condition names the status.
  status.summary(DiagnosticStatus::OK, "mapping normally");
  if (tracker_failures > diagnosed_tracker_failures_) {
    status.mergeSummary(DiagnosticStatus::WARN, "scan matching failed (odometry used)");
  }
  if (dropped > diagnosed_dropped_) {
    status.mergeSummary(DiagnosticStatus::WARN,
                        "scans dropped (missing TF, full queue or time going backwards)");
  }
  if (received == 0) {
    status.mergeSummary(DiagnosticStatus::WARN, "no scans yet");
  } else if ((ros::WallTime::now() - last_scan).toSec() >
             node_options_.diagnostics_scan_timeout_s) {
    status.mergeSummary(DiagnosticStatus::ERROR, "no scans processed recently");
  }
  diagnosed_dropped_ = dropped;
  diagnosed_tracker_failures_ = tracker_failures;

  status.add("mode", mode);
  status.add("session", session);
  status.add("nodes", nodes);
  status.add("scans received", received);
  status.add("scans processed", processed);
  status.add("scans skipped", skipped);
  status.add("scans dropped (no TF)", static_cast<std::uint64_t>(scans_dropped_no_tf_));
  status.add("scans dropped (queue full)", static_cast<std::uint64_t>(scans_dropped_queue_full_));
  status.add("scans refused (time backwards)",
             static_cast<std::uint64_t>(scans_refused_time_backwards_));
  status.add("sessions started (time backwards)",
             static_cast<std::uint64_t>(sessions_started_time_backwards_));
  status.add("scans queued", queued);
  status.add("tracker failures", tracker_failures);
  status.add("loop closures accepted", closures);
  status.add("merges", merges);
}

}  // namespace longterm_mapper2d_ros
