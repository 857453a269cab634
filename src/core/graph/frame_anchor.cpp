#include "longterm_mapper2d/core/graph/frame_anchor.h"

#include <algorithm>
#include <vector>

namespace longterm_mapper2d {
namespace {

// Median of a non-empty list (the mean of the middle two for an even count).
double Median(std::vector<double> values) {
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  const double upper = values[mid];
  if (values.size() % 2 == 1) return upper;
  return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + mid));
}

}  // namespace

std::optional<Pose2> FrameCorrection(const PoseGraph& graph,
                                     const std::map<GraphNodeId, Pose2>& map_T_node_anchors) {
  std::vector<std::pair<Pose2, Pose2>> pairs;  // (current, anchor)
  for (const auto& [id, anchor] : map_T_node_anchors) {
    if (!graph.HasNode(id) || !anchor.IsFinite()) continue;
    pairs.emplace_back(graph.node(id).pose, anchor);
  }
  if (pairs.empty()) return std::nullopt;
  // Offsets taken about the first one, so that a cluster around +-pi has no seam.
  const double reference =
      NormalizeAngle(pairs.front().second.theta() - pairs.front().first.theta());
  std::vector<double> heading_offsets;
  for (const auto& [current, anchor] : pairs) {
    heading_offsets.push_back(NormalizeAngle(anchor.theta() - current.theta() - reference));
  }
  const double phi = NormalizeAngle(reference + Median(heading_offsets));
  const Pose2 rotation(0.0, 0.0, phi);
  std::vector<double> dx, dy;
  for (const auto& [current, anchor] : pairs) {
    const Eigen::Vector2d rotated = rotation * current.translation();
    dx.push_back(anchor.x() - rotated.x());
    dy.push_back(anchor.y() - rotated.y());
  }
  return Pose2(Median(dx), Median(dy), phi);
}

void MoveFrame(PoseGraph& graph, const Pose2& correction) {
  for (const auto& [id, node] : graph.nodes()) {
    graph.mutable_node(id).pose = correction * node.pose;
  }
}

}  // namespace longterm_mapper2d
