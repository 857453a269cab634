#pragma once

#include <map>

#include "longterm_mapper2d/core/mapping/local_map.h"

namespace longterm_mapper2d {

// Drops the waypoints that a later session has seen again: a waypoint goes when a kept waypoint
// of a strictly newer session lies within `distance_m` and `angle_rad` of it (both placed in the
// map by their nodes' current poses), whichever nodes hold the two. Sessions are visited newest
// first, so a waypoint is only ever dropped for one that stays, and the newest session's
// waypoints are never dropped. Returns the number dropped.
//
// Why: a merge keeps the old node's waypoints unless one of the surviving node's own covers
// them, but nodes that no closure joined still overlap, so every session that drives a corridor
// a little differently left its old views behind and the map file grew with the sessions (intel
// ten times: 2259 -> 3986 waypoints, 3.5 of 4 in ten with a nearby one on another node). The
// grid is rendered oldest first, so an older scan covered by a newer one from the same place
// only ever repeated what the newer one overwrites.
int DropWaypointsSeenAgain(std::map<NodeId, LocalMapNode>* nodes, double distance_m,
                           double angle_rad);

}  // namespace longterm_mapper2d
