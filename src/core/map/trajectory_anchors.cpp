#include "longterm_mapper2d/core/map/trajectory_anchors.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>

#include "longterm_mapper2d/core/io/atomic_file.h"
#include "longterm_mapper2d/core/io/number_table.h"

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
  const auto rows = ReadNumberTable(path, 5, "'stamp node x y theta'");
  if (!rows.ok()) return rows.status();
  std::vector<AnchoredPose> anchors;
  anchors.reserve(rows->size());
  for (const NumberRow& row : *rows) {
    const std::vector<double>& v = row.values;
    // Node ids are integers from kMapFrame up; doubles hold them exactly below 2^53.
    if (v[1] != std::floor(v[1]) || v[1] < static_cast<double>(kMapFrame) || v[1] > 9.0e15) {
      return Status::Error(path + ":" + std::to_string(row.line_number) +
                           ": the node must be an integer from " + std::to_string(kMapFrame) +
                           " up, got " + std::to_string(v[1]));
    }
    anchors.push_back({v[0], static_cast<NodeId>(v[1]), Pose2(v[2], v[3], v[4])});
  }
  return anchors;
}

}  // namespace longterm_mapper2d
