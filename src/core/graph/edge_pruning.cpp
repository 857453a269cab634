#include "longterm_mapper2d/core/graph/edge_pruning.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <deque>
#include <limits>
#include <set>
#include <unordered_map>
#include <vector>

namespace longterm_mapper2d {
namespace {

struct Strength {
  double weakest = 0.0;    // smallest eigenvalue of the information
  double strongest = 0.0;  // largest
};

Strength EdgeStrength(const Eigen::Matrix3d& information) {
  if (!information.allFinite()) return {};
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (information + information.transpose()),
                                                     Eigen::EigenvaluesOnly);
  return {eig.eigenvalues().minCoeff(), eig.eigenvalues().maxCoeff()};
}

// Whether a and b are joined by the edges not marked removed.
bool Connected(const PoseGraph& graph, const std::vector<bool>& removed,
               const std::unordered_map<GraphNodeId, std::vector<std::size_t>>& incident,
               GraphNodeId a, GraphNodeId b) {
  std::set<GraphNodeId> seen{a};
  std::deque<GraphNodeId> queue{a};
  while (!queue.empty()) {
    const GraphNodeId at = queue.front();
    queue.pop_front();
    if (at == b) return true;
    for (std::size_t i : incident.at(at)) {
      if (removed[i]) continue;
      const GraphEdge& e = graph.edges()[i];
      const GraphNodeId other = e.from == at ? e.to : e.from;
      if (seen.insert(other).second) queue.push_back(other);
    }
  }
  return false;
}

}  // namespace

int PruneNegligibleCondensedEdges(PoseGraph* graph, double ratio) {
  if (!(ratio > 0.0)) return 0;
  const std::vector<GraphEdge>& edges = graph->edges();
  std::vector<Strength> strength(edges.size());
  std::unordered_map<GraphNodeId, std::vector<std::size_t>> incident;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    strength[i] = EdgeStrength(edges[i].information);
    incident[edges[i].from].push_back(i);
    incident[edges[i].to].push_back(i);
  }
  // The weakest direction of the strongest other edge at `node`.
  auto best_other = [&](GraphNodeId node, std::size_t except) {
    double best = 0.0;
    for (std::size_t i : incident.at(node)) {
      if (i != except) best = std::max(best, strength[i].weakest);
    }
    return best;
  };
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (edges[i].kind != EdgeKind::kCondensed) continue;
    const double reference = std::min(best_other(edges[i].from, i), best_other(edges[i].to, i));
    if (strength[i].strongest < ratio * reference) candidates.push_back(i);
  }
  if (candidates.empty()) return 0;
  std::sort(candidates.begin(), candidates.end(), [&](std::size_t a, std::size_t b) {
    return strength[a].strongest < strength[b].strongest;
  });
  std::vector<bool> removed(edges.size(), false);
  int count = 0;
  for (std::size_t i : candidates) {
    removed[i] = true;
    if (Connected(*graph, removed, incident, edges[i].from, edges[i].to)) {
      ++count;
    } else {
      removed[i] = false;
    }
  }
  std::vector<GraphEdge> kept;
  kept.reserve(edges.size() - count);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (!removed[i]) kept.push_back(edges[i]);
  }
  graph->mutable_edges() = std::move(kept);
  return count;
}

}  // namespace longterm_mapper2d
