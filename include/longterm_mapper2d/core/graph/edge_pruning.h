#pragma once

#include "longterm_mapper2d/core/graph/pose_graph.h"

namespace longterm_mapper2d {

// Removes condensed edges that say next to nothing: an edge goes when even its strongest
// direction (the largest eigenvalue of its information) is below `ratio` times the weakest
// direction of the strongest other edge at each of its two nodes, and its two nodes stay
// connected without it. Weakest edges first. Returns the number removed. Dropping information
// can only make the graph less confident, never more.
//
// Why: a spanning tree of condensed edges must reach every neighbour of a removed node, so a
// neighbour tied to the region by a useless edge gets a new useless edge at every merge, scaled
// down again each time. After hours of patrol such edges (information 1e-10 down to 1e-105 next
// to 1e2) crowd every node (13 neighbours), make the local systems numerically singular, and
// condensation falls back to composed paths that keep 1/k of the information.
int PruneNegligibleCondensedEdges(PoseGraph* graph, double ratio);

}  // namespace longterm_mapper2d
