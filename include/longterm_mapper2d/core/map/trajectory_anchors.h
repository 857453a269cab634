#pragma once

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
};

// The poses in the frame of `map`: through their node, or through the node that took a removed
// one over. A node the map never had (a trajectory of another map) is an error that names it.
StatusOr<std::vector<StampedPose2>> ReexpressTrajectory(const SessionMap& map,
                                                        const std::vector<AnchoredPose>& anchors);

// Text files, one pose per line: `stamp node x y theta` (seconds, node id, metres, radians);
// blank lines and lines starting with '#' are ignored.
Status WriteTrajectoryAnchors(const std::string& path, const std::vector<AnchoredPose>& anchors);
StatusOr<std::vector<AnchoredPose>> ReadTrajectoryAnchors(const std::string& path);

}  // namespace longterm_mapper2d
