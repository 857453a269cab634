#pragma once

#include <map>
#include <vector>

#include "longterm_mapper2d/core/mapping/local_map.h"

namespace longterm_mapper2d {

// How far a node's scans reach from another node's origin: the largest distance of the node's
// origin and of its waypoints from `survivor`'s origin, both nodes placed by their current poses.
double ReachFrom(const LocalMapNode& survivor, const LocalMapNode& node);

// The members of a merge set that are merged: the set's ids sorted oldest first, the last (the
// newest) survives and is always kept; every other member only if ReachFrom(survivor, member) is
// at most `max_extent_m` (0: no limit). Returns the kept ids in the same order.
//
// Why: a merge ties the removed node's cloud and scans to the survivor for good, placed by one
// relative pose of the graph, so a merged local map is rigid. When the merged sets chain (each
// new node closing with the last survivor, which holds everything before it), a survivor ends up
// holding scans far from its origin (intel's default run: up to 15 m), and every later closure's
// rotation error moves them by that lever arm. Intel's first pass along its east corridor,
// carried through 22 merges in the rooms next to it, read 0.10-0.25 m (1-2.5 deg) against its
// second pass, 0.01-0.06 m without maintenance. A member left out keeps its node and its
// closures, and may merge later with a node nearer to it. Off by default: the simulated care
// home pays for it (MaintenanceOptions::merge_max_extent_m).
std::vector<NodeId> MergeMembersWithinExtent(const std::map<NodeId, LocalMapNode>& nodes,
                                             const std::vector<NodeId>& ids, double max_extent_m);

}  // namespace longterm_mapper2d
