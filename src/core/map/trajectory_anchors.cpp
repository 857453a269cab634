#include "longterm_mapper2d/core/map/trajectory_anchors.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>

#include "longterm_mapper2d/core/io/atomic_file.h"
#include "longterm_mapper2d/core/io/number_table.h"
#include "longterm_mapper2d/core/mapping/trajectory_smoothing.h"

namespace longterm_mapper2d {

StatusOr<std::vector<StampedPose2>> ReexpressTrajectory(const SessionMap& map,
                                                        const std::vector<AnchoredPose>& anchors,
                                                        double half_window_s) {
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
  if (half_window_s > 0.0) {
    // Runs of poses that hang off nodes, smoothed along the poses as written.
    std::vector<double> stamps;
    std::vector<bool> in_run;
    std::vector<Pose2> map_T_base, written;
    for (std::size_t i = 0; i < anchors.size(); ++i) {
      stamps.push_back(anchors[i].stamp_s);
      in_run.push_back(anchors[i].node != kMapFrame && anchors[i].written.has_value());
      map_T_base.push_back(trajectory[i].pose);
      written.push_back(anchors[i].written.value_or(trajectory[i].pose));
    }
    SmoothStretches(stamps, in_run, written, half_window_s, map_T_base);
    for (std::size_t i = 0; i < trajectory.size(); ++i) trajectory[i].pose = map_T_base[i];
  }
  return trajectory;
}

Status WriteTrajectoryAnchors(const std::string& path, const std::vector<AnchoredPose>& anchors) {
  std::string text =
      "# stamp node x y theta [x_w y_w theta_w]: the base in the frame of the node (node -1: "
      "map) [and in the map frame as the session wrote it]\n";
  char line[256];
  for (const AnchoredPose& a : anchors) {
    int n =
        std::snprintf(line, sizeof(line), "%.6f %" PRId64 " %.6f %.6f %.6f", a.stamp_s,
                      static_cast<std::int64_t>(a.node), a.pose.x(), a.pose.y(), a.pose.theta());
    if (a.written) {
      n += std::snprintf(line + n, sizeof(line) - n, " %.6f %.6f %.6f", a.written->x(),
                         a.written->y(), a.written->theta());
    }
    text.append(line, n);
    text += '\n';
  }
  return WriteFileAtomically(path, text);
}

StatusOr<std::vector<AnchoredPose>> ReadTrajectoryAnchors(const std::string& path) {
  const auto rows = ReadNumberTable(path, {5, 8}, "'stamp node x y theta [x_w y_w theta_w]'");
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
    anchors.push_back({v[0], static_cast<NodeId>(v[1]), Pose2(v[2], v[3], v[4]), std::nullopt});
    if (v.size() == 8) anchors.back().written = Pose2(v[5], v[6], v[7]);
  }
  return anchors;
}

}  // namespace longterm_mapper2d
