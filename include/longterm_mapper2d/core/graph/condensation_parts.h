#pragma once

#include <Eigen/Core>
#include <vector>

#include "longterm_mapper2d/core/graph/pose_graph.h"

namespace longterm_mapper2d {

// One connected part of the local factor set of a node removal (the edges touching the removed
// nodes), and the ways RemoveNodesCondensed keeps its information (ALGORITHMS.md §9.3). All work
// on `graph` at its current estimate, which the caller has optimised with the part's gauge fixed.
struct CondensationPart {
  std::vector<GraphNodeId> removed;
  std::vector<GraphNodeId> neighbours;  // remaining nodes, the part's gauge excluded
  std::vector<std::size_t> edges;       // indices into graph.edges()
  GraphNodeId gauge = 0;
};

// The neighbours' information on their additive increments (one 3x3 block each, gauge fixed)
// from the exact marginal of the part, for a star from the gauge, scaled by `scale` <= 1 so that
// the star is never more confident than the marginal. False if the part is rank deficient.
bool LocalStarMarginals(const PoseGraph& graph, const CondensationPart& part,
                        std::vector<Eigen::Matrix3d>* h, double* scale);

// The exact marginal of the part as a spanning tree of edges over the gauge and the neighbours
// (from, to, measurement and information set), scaled by `scale` <= 1 so that the tree is never
// more confident than the marginal. False if the part is rank deficient.
bool LocalTreeEdges(const PoseGraph& graph, const CondensationPart& part,
                    std::vector<GraphEdge>* edges, double* scale);

// The released code's star: each neighbour's marginal from the whole graph, gauge fixed.
bool WholeGraphMarginals(const PoseGraph& graph, const CondensationPart& part,
                         std::vector<Eigen::Matrix3d>* h);

// The fallback star for a rank-deficient part: poses composed along a breadth-first tree from the
// gauge; `valid` false for a neighbour behind a singular edge (it gets no edge).
void ComposedMarginals(const PoseGraph& graph, const CondensationPart& part,
                       std::vector<Eigen::Matrix3d>* h, std::vector<bool>* valid);

}  // namespace longterm_mapper2d
