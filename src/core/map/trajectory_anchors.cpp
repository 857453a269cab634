#include "longterm_mapper2d/core/map/trajectory_anchors.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "longterm_mapper2d/core/io/atomic_file.h"

namespace longterm_mapper2d {

StatusOr<std::vector<StampedPose2>> ReexpressTrajectory(const SessionMap& map,
                                                        const std::vector<AnchoredPose>& anchors) {
  std::vector<StampedPose2> trajectory;
  trajectory.reserve(anchors.size());
  for (const AnchoredPose& anchor : anchors) {
    if (anchor.node == kMapFrame) {
      trajectory.push_back({anchor.stamp_s, anchor.pose});
      continue;
    }
    if (const auto node = map.nodes.find(anchor.node); node != map.nodes.end()) {
      trajectory.push_back({anchor.stamp_s, node->second.map_T_node * anchor.pose});
      continue;
    }
    const auto removed = map.removed_nodes.find(anchor.node);
    if (removed == map.removed_nodes.end()) {
      return Status::Error("node " + std::to_string(anchor.node) +
                           " is neither in the map nor among its removed nodes (a trajectory of "
                           "another map?)");
    }
    const auto survivor = map.nodes.find(removed->second.survivor);
    if (survivor == map.nodes.end()) {
      return Status::Error("removed node " + std::to_string(anchor.node) +
                           " refers to a missing node");
    }
    trajectory.push_back({anchor.stamp_s, survivor->second.map_T_node *
                                              removed->second.survivor_T_removed * anchor.pose});
  }
  return trajectory;
}

Status WriteTrajectoryAnchors(const std::string& path, const std::vector<AnchoredPose>& anchors) {
  std::string text = "# stamp node x y theta: the base in the frame of the node (node -1: map)\n";
  char line[192];
  for (const AnchoredPose& a : anchors) {
    std::snprintf(line, sizeof(line), "%.6f %" PRId64 " %.6f %.6f %.6f\n", a.stamp_s,
                  static_cast<std::int64_t>(a.node), a.pose.x(), a.pose.y(), a.pose.theta());
    text += line;
  }
  return WriteFileAtomically(path, text);
}

StatusOr<std::vector<AnchoredPose>> ReadTrajectoryAnchors(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Status::Error("cannot open '" + path + "'");
  std::vector<AnchoredPose> anchors;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    AnchoredPose anchor;
    std::int64_t node = 0;
    double x, y, theta;
    std::string extra;
    if (!(fields >> anchor.stamp_s >> node >> x >> y >> theta) || (fields >> extra) ||
        node < kMapFrame) {
      return Status::Error(path + ":" + std::to_string(line_number) +
                           ": expected 'stamp node x y theta', got '" + line + "'");
    }
    anchor.node = node;
    anchor.pose = Pose2(x, y, theta);
    if (!anchor.pose.IsFinite() || !std::isfinite(anchor.stamp_s)) {
      return Status::Error(path + ":" + std::to_string(line_number) + ": non-finite value");
    }
    anchors.push_back(anchor);
  }
  return anchors;
}

}  // namespace longterm_mapper2d
