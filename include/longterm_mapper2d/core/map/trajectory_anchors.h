#pragma once

#include <optional>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/map/session_map_file.h"

namespace longterm_mapper2d {

// A pose of a trajectory kept the way the mapper keeps it: the base in the frame of a local-map
// node. Re-expressed through a later map (after later sessions moved, merged and removed nodes),
// it follows every correction since, as the poses of the current session do.
constexpr NodeId kMapFrame = -1;
struct AnchoredPose {
  double stamp_s = 0.0;
  // The node the pose hangs off; kMapFrame: the pose is map_T_base and fixed (recorded while
  // localizing on a frozen map).
  NodeId node = kMapFrame;
  Pose2 pose;  // node_T_base, or map_T_base for kMapFrame
  // map_T_base as the session wrote it (its trajectory, smoothed across local maps): the chain
  // along which the re-expressed poses are smoothed again. Absent in five-column files.
  std::optional<Pose2> written;
};

// The poses in the frame of `map`: through their node, or through the node that took a removed
// one over. A node the map never had (a trajectory of another map) is an error that names it.
// With half_window_s > 0, runs of poses that hang off nodes and carry `written` are smoothed as
// the mapper smooths its own trajectory (SmoothAcrossLocalMaps, the written poses as the chain):
// scans a few seconds apart whose local maps were merged into different survivors would
// otherwise jump by whatever the later graph moved those survivors by (intel in three parts:
// 25 cm between two scans 1 s apart). In the map that wrote them the poses come back unchanged.
StatusOr<std::vector<StampedPose2>> ReexpressTrajectory(const SessionMap& map,
                                                        const std::vector<AnchoredPose>& anchors,
                                                        double half_window_s = 0.0);

// Text files, one pose per line: `stamp node x y theta [x_w y_w theta_w]` (seconds, node id,
// metres, radians; the optional last three the written pose); blank lines and lines starting
// with '#' are ignored.
Status WriteTrajectoryAnchors(const std::string& path, const std::vector<AnchoredPose>& anchors);
StatusOr<std::vector<AnchoredPose>> ReadTrajectoryAnchors(const std::string& path);

}  // namespace longterm_mapper2d
