#include "longterm_mapper2d/core/mapping/waypoint_thinning.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace longterm_mapper2d {
namespace {

struct Placed {
  int session_id;
  Pose2 map_T_base;
  NodeId node;
  std::size_t index;
};

// Cells packed into one key (shifting the unsigned pattern: a negative cell must not be shifted).
std::uint64_t CellKey(std::int64_t cx, std::int64_t cy) {
  return (static_cast<std::uint64_t>(cx) << 32) ^ static_cast<std::uint32_t>(cy);
}

}  // namespace

int DropWaypointsSeenAgain(std::map<NodeId, LocalMapNode>* nodes, double distance_m,
                           double angle_rad) {
  std::vector<Placed> all;
  for (const auto& [id, node] : *nodes) {
    for (std::size_t i = 0; i < node.waypoints.size(); ++i) {
      const Waypoint& w = node.waypoints[i];
      all.push_back({w.session_id, node.map_T_node * w.node_T_base, id, i});
    }
  }
  if (all.empty()) return 0;
  std::stable_sort(all.begin(), all.end(),
                   [](const Placed& a, const Placed& b) { return a.session_id > b.session_id; });

  // Kept waypoints hashed by cells of distance_m: any cover lies in the 3 x 3 cells around.
  const double cell_m = std::max(distance_m, 1e-3);
  auto cell_of = [cell_m](const Pose2& pose) {
    return std::make_pair(static_cast<std::int64_t>(std::floor(pose.x() / cell_m)),
                          static_cast<std::int64_t>(std::floor(pose.y() / cell_m)));
  };
  std::unordered_map<std::uint64_t, std::vector<Pose2>> kept;
  auto covered = [&](const Pose2& pose) {
    const auto [cx, cy] = cell_of(pose);
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto it = kept.find(CellKey(cx + dx, cy + dy));
        if (it == kept.end()) continue;
        for (const Pose2& other : it->second) {
          const Pose2 d = other.Between(pose);
          if (d.translation().norm() <= distance_m && std::abs(d.theta()) <= angle_rad) {
            return true;
          }
        }
      }
    }
    return false;
  };

  std::map<NodeId, std::vector<bool>> drop;
  for (const auto& [id, node] : *nodes) drop[id].assign(node.waypoints.size(), false);
  int dropped = 0;
  for (std::size_t begin = 0; begin < all.size();) {
    // One session at a time: its waypoints are tested against newer sessions only, then join
    // the kept set.
    std::size_t end = begin;
    while (end < all.size() && all[end].session_id == all[begin].session_id) ++end;
    std::vector<const Placed*> survivors;
    for (std::size_t k = begin; k < end; ++k) {
      if (covered(all[k].map_T_base)) {
        drop[all[k].node][all[k].index] = true;
        ++dropped;
      } else {
        survivors.push_back(&all[k]);
      }
    }
    for (const Placed* p : survivors) {
      const auto [cx, cy] = cell_of(p->map_T_base);
      kept[CellKey(cx, cy)].push_back(p->map_T_base);
    }
    begin = end;
  }
  if (dropped == 0) return 0;
  for (auto& [id, node] : *nodes) {
    const std::vector<bool>& gone = drop.at(id);
    std::vector<Waypoint> remaining;
    remaining.reserve(node.waypoints.size());
    for (std::size_t i = 0; i < node.waypoints.size(); ++i) {
      if (!gone[i]) remaining.push_back(std::move(node.waypoints[i]));
    }
    node.waypoints = std::move(remaining);
  }
  return dropped;
}

}  // namespace longterm_mapper2d
