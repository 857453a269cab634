#include "longterm_mapper2d/core/mapping/merge_extent.h"

#include <algorithm>

namespace longterm_mapper2d {

double ReachFrom(const LocalMapNode& survivor, const LocalMapNode& node) {
  const Pose2 survivor_T_node = survivor.map_T_node.Between(node.map_T_node);
  double reach_m = survivor_T_node.translation().norm();
  for (const Waypoint& w : node.waypoints) {
    reach_m = std::max(reach_m, (survivor_T_node * w.node_T_base).translation().norm());
  }
  return reach_m;
}

std::vector<NodeId> MergeMembersWithinExtent(const std::map<NodeId, LocalMapNode>& nodes,
                                             const std::vector<NodeId>& ids, double max_extent_m) {
  if (max_extent_m <= 0.0 || ids.empty()) return ids;
  const LocalMapNode& survivor = nodes.at(ids.back());
  std::vector<NodeId> kept;
  for (std::size_t i = 0; i + 1 < ids.size(); ++i) {
    if (ReachFrom(survivor, nodes.at(ids[i])) <= max_extent_m) kept.push_back(ids[i]);
  }
  kept.push_back(ids.back());
  return kept;
}

}  // namespace longterm_mapper2d
