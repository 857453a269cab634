// Loop closing of the Mapper (ALGORITHMS.md §7-8): the search from each new node, the vote, and
// the final check at the end of a session.
#include <algorithm>

#include "longterm_mapper2d/core/mapping/mapper.h"

namespace longterm_mapper2d {

void Mapper::CloseLoops(NodeId node, bool force) {
  if (!options_.loop_closing.enabled) return;
  ScopedStageTimer timer(stats_.stage_times, "loop_closing");
  loop_closer_.SearchFrom(
      graph_, node, [this](GraphNodeId id) -> const Cloud& { return nodes_.at(id).cloud; }, stats_,
      doubtful_since_.has_value());
  AcceptClosures(loop_closer_.Vote(graph_, force, stats_));
}

void Mapper::AcceptClosures(const std::vector<GraphEdge>& closures) {
  for (const GraphEdge& edge : closures) {
    if (doubtful_since_ && std::max(edge.from, edge.to) >= *doubtful_since_ &&
        std::min(edge.from, edge.to) < *doubtful_since_) {
      doubtful_since_.reset();
    }
  }
  for (const GraphEdge& edge : closures) graph_.AddEdge(edge);
  if (!closures.empty()) OptimizeGraph(options_.loop_closing.optimizer_iterations);
  QueueMerges(closures);
  MergeReadySets();
}

void Mapper::FinalClosureCheck() {
  // Merges queued by this check or waiting for younger nodes happen now (merge_delay_nodes).
  finishing_ = true;
  bool already_optimized = false;
  if (options_.loop_closing.enabled) {
    // Every node was searched when it was made: what is left is the vote on the candidates
    // still waiting for later nodes.
    {
      ScopedStageTimer timer(stats_.stage_times, "loop_closing");
      AcceptClosures(loop_closer_.Vote(graph_, /*force=*/true, stats_));
    }
    if (options_.loop_closing.final_sweep) {
      OptimizeGraph(options_.optimizer.max_iterations);
      // Whatever the sweep changes in the graph (closures added, merges, inconsistent closures
      // taken out) is followed by an optimisation; a sweep that ran none left the graph as
      // optimised just above.
      const auto optimizations_before = stats_.counters["optimizations"];
      SweepClosures();
      already_optimized = stats_.counters["optimizations"] == optimizations_before;
    }
  }
  if (!already_optimized) OptimizeGraph(options_.optimizer.max_iterations);
  finishing_ = false;
}

void Mapper::SweepClosures() {
  ScopedStageTimer timer(stats_.stage_times, "loop_closing_sweep");
  std::vector<NodeId> ids;
  for (const auto& [id, node] : graph_.nodes()) {
    if (node.session_id == session_id_) ids.push_back(id);
  }
  const auto accepted_before = stats_.counters["loop_closures_accepted"];
  for (std::size_t k = 0; k < ids.size(); ++k) {
    // A node an earlier closure of the sweep merged away is not searched; the vote still runs.
    if (graph_.HasNode(ids[k])) {
      loop_closer_.SweepFrom(
          graph_, ids[k], [this](GraphNodeId id) -> const Cloud& { return nodes_.at(id).cloud; },
          stats_);
    }
    AcceptClosures(loop_closer_.Vote(graph_, k + 1 == ids.size(), stats_));
  }
  stats_.counters["loop_closures_accepted_in_sweep"] +=
      stats_.counters["loop_closures_accepted"] - accepted_before;
}

}  // namespace longterm_mapper2d
