#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d {

// Where the offline mapper finds scans and odometry in a recording (ROS bags): the options of
// its command line that the recording reader needs.
struct RecordingOptions {
  std::string scan_topic = "/scan";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  // If set, odometry comes from this nav_msgs/Odometry topic instead of /tf.
  std::string odom_topic;
  // Window in seconds from the first message, like `rosbag play -s/-u`; end < 0 means to the end.
  double start_s = 0.0;
  double end_s = -1.0;
};

// Scans with their odometry, in stamp order, from a recording.
class RecordedScans {
 public:
  virtual ~RecordedScans() = default;
  // Scans in the window (for progress reporting).
  virtual std::uint64_t scan_count() const = 0;
  // Calls `visit` for each scan in order; an error if the recording cannot be read.
  virtual Status ForEach(const std::function<void(const ScanInput&)>& visit) = 0;
  // Scans dropped because no odometry covered them (known after ForEach).
  virtual std::uint64_t scans_without_odometry() const = 0;
  virtual std::vector<std::string> warnings() const = 0;
};

using RecordingOpener = std::function<StatusOr<std::unique_ptr<RecordedScans>>(
    const std::vector<std::string>& paths, const RecordingOptions& options)>;

// The offline mapper: bags or a CARMEN log in, trajectory, map and statistics out. Runs the same
// core façade as mapper_node, with no roscore. Deterministic. CARMEN logs are read by the core;
// bags by `open_bags`, which the ROS build supplies (empty: `--bag` is refused with the reason,
// as in the ROS-free build).
// Returns the process exit code (0 ok, 1 failure while mapping or writing, 2 bad arguments/input).
int RunOfflineMapper(int argc, char** argv, const RecordingOpener& open_bags);

}  // namespace longterm_mapper2d
