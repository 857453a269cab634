#pragma once

#include <map>

#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/graph/pose_graph.h"

namespace longterm_mapper2d {
namespace test_support {

// A graph of nodes at the given poses, without edges.
PoseGraph NodesAt(const std::map<GraphNodeId, Pose2>& poses);

}  // namespace test_support
}  // namespace longterm_mapper2d
