// Path lengths through the pose graph, for the loop closer's candidate and chain gates.
#include <functional>
#include <queue>
#include <utility>
#include <vector>

#include "longterm_mapper2d/core/loop_closing/loop_closer.h"

namespace longterm_mapper2d {
namespace {

// Shortest path lengths from `source` over the edges `use` admits, within `limit`.
template <class EdgeFilter>
std::map<GraphNodeId, double> PathLengths(const PoseGraph& graph, GraphNodeId source, double limit,
                                          const EdgeFilter& use) {
  std::map<GraphNodeId, std::vector<GraphNodeId>> adjacency;
  for (const GraphEdge& e : graph.edges()) {
    if (!use(e)) continue;
    adjacency[e.from].push_back(e.to);
    adjacency[e.to].push_back(e.from);
  }
  std::map<GraphNodeId, double> distance{{source, 0.0}};
  using Entry = std::pair<double, GraphNodeId>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  queue.emplace(0.0, source);
  while (!queue.empty()) {
    const auto [d, id] = queue.top();
    queue.pop();
    if (d > distance[id]) continue;
    for (GraphNodeId next : adjacency[id]) {
      const double nd =
          d + (graph.node(next).pose.translation() - graph.node(id).pose.translation()).norm();
      if (nd > limit) continue;
      auto it = distance.find(next);
      if (it == distance.end() || nd < it->second) {
        distance[next] = nd;
        queue.emplace(nd, next);
      }
    }
  }
  return distance;
}

}  // namespace

std::map<GraphNodeId, double> OdometryPathLengths(const PoseGraph& graph, GraphNodeId source,
                                                  double limit, bool tracker_chain_only) {
  const int session = graph.node(source).session_id;
  return PathLengths(graph, source, limit, [&](const GraphEdge& e) {
    return e.kind == EdgeKind::kOdometry &&
           (!tracker_chain_only ||
            (graph.node(e.from).session_id == session && graph.node(e.to).session_id == session));
  });
}

std::map<GraphNodeId, double> GraphPathLengths(const PoseGraph& graph, GraphNodeId source,
                                               double limit) {
  return PathLengths(graph, source, limit, [](const GraphEdge&) { return true; });
}

}  // namespace longterm_mapper2d
