#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/graph/pose_graph.h"

namespace longterm_mapper2d {

// How the information of removed nodes is kept (ALGORITHMS.md §9.3, §14).
enum class CondensationMode {
  // The principled version: the local factor set (the edges touching the removed nodes) is
  // optimised with the gauge fixed and marginalised exactly (a dense Schur complement); the
  // result becomes a spanning tree of edges over the gauge and the neighbours, made of the most
  // certain relative poses of that marginal, scaled so that it is never more confident than it.
  kLocalTree,
  // The same marginal kept as one star edge from the gauge to each neighbour (the neighbours'
  // correlations are lost, so the conservative scale weakens the star), as ALGORITHMS.md §14 puts
  // it.
  kLocalStar,
  // The released code's version: marginals of each neighbour from the whole graph (information
  // that the surviving edges also carry is counted twice), no scaling.
  kWholeGraph,
};

// The mode a `maintenance.condensation` option names ("local_tree", "local_star", "whole_graph").
std::optional<CondensationMode> CondensationModeFromName(const std::string& name);

struct CondensationReport {
  int removed_nodes = 0;
  int removed_edges = 0;
  int added_edges = 0;     // new condensed edges
  int fused_edges = 0;     // condensed information fused into an edge that already joined the pair
  int composed_edges = 0;  // from the composed-path fallback (rank-deficient local system)
  int dropped_edges = 0;   // neighbours left without any information to keep
  double scale = 1.0;      // the conservative scale of the last local tree or star (1: exact)
};

// Removes `removed` from the graph and replaces the information their edges carried about the
// remaining nodes by condensed edges among `gauge` (a remaining node, normally the one that now
// holds the merged local map) and the neighbours of the removed nodes (a tree or a star from the
// gauge, by `mode`). A neighbour reached only through removed nodes that do not touch the gauge
// is condensed with the newest neighbour of its own connected part as the gauge instead. If the
// gauge of the graph is removed, `gauge` becomes it. New and fused edges have kind kCondensed and
// carry `session_id` and `stamp_s`.
StatusOr<CondensationReport> RemoveNodesCondensed(PoseGraph& graph,
                                                  const std::vector<GraphNodeId>& removed,
                                                  GraphNodeId gauge, CondensationMode mode,
                                                  int session_id, double stamp_s);

// The Gauss-Newton information matrix (J' Omega J summed over `edges`, no robust loss) of the
// graph at its current estimate, in additive (x, y, theta) increments of the nodes in `order`
// (3 rows per node). Edges to nodes outside `order` contribute only to the listed nodes.
Eigen::MatrixXd DenseInformation(const PoseGraph& graph, const std::vector<std::size_t>& edges,
                                 const std::vector<GraphNodeId>& order);

// The information of an edge from -> to at measurement from^-1 to, given the information H_free
// (3x3, additive increments) it must put on one of its nodes with the other held fixed:
// Omega = J^-T H_free J^-1 with J the edge error's Jacobian with respect to the free node.
Eigen::Matrix3d EdgeInformationFromNodeInformation(const Pose2& from, const Pose2& to,
                                                   const Eigen::Matrix3d& h_free, bool free_is_to);

// Fuses two Gaussian measurements of the same relative pose (both edges from -> to): information
// adds, the measurement is the information-weighted mean in the tangent space at b.
GraphEdge FuseEdges(const GraphEdge& a, const GraphEdge& b);

}  // namespace longterm_mapper2d
