#pragma once

#include <map>
#include <optional>

#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/graph/pose_graph.h"

namespace longterm_mapper2d {

// The map frame held by where a set of nodes were (their anchors, map_T_node as a loaded map had
// them) instead of by the one node the optimiser keeps fixed.
//
// Why: over many sessions merges hand the gauge from node to node, and the gauge can end up on a
// node tied to the rest only by condensed edges that say almost nothing. The rest then settles
// turned about it (a ten-hour patrol had a whole hour's map turned by 24.5 degrees, consistent in
// itself). Moving the solution rigidly afterwards changes no relative pose, so the shape is the
// one the fixed gauge gave; only the frame is chosen by the anchored nodes.
//
// Robust on purpose: a few weakly tied nodes may be turned far off, and a mean over all anchored
// nodes follows them (tried: the mean of the heading offsets left the bulk of that map turned by
// 2.5 degrees to balance a handful turned by -24). So the correction T (the new poses are
// T * map_T_node) takes the heading from the median of the anchored nodes' heading offsets
//   phi = median_i wrap(theta_A_i - theta_i)
// and the position from the component-wise median of the remaining offsets
//   v = median_i (t_A_i - R(phi) t_i).
// Anchors of nodes not in the graph are ignored; nullopt if none is in it.
std::optional<Pose2> FrameCorrection(const PoseGraph& graph,
                                     const std::map<GraphNodeId, Pose2>& map_T_node_anchors);

// Moves every node of the graph rigidly: pose <- correction * pose.
void MoveFrame(PoseGraph& graph, const Pose2& correction);

}  // namespace longterm_mapper2d
