#pragma once

#include <Eigen/Core>
#include <map>
#include <utility>
#include <vector>

#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/graph/pose_graph.h"

namespace longterm_mapper2d {
namespace test_support {

// A graph of nodes at the given poses, without edges.
PoseGraph NodesAt(const std::map<GraphNodeId, Pose2>& poses);

// A graph of nodes at `poses` joined by odometry edges (measured as the poses have it) with the
// diagonal `information`.
PoseGraph OdometryGraph(const std::map<GraphNodeId, Pose2>& poses,
                        const std::vector<std::pair<GraphNodeId, GraphNodeId>>& odometry,
                        const Eigen::Vector3d& information);

}  // namespace test_support
}  // namespace longterm_mapper2d
