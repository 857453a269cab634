#include "longterm_mapper2d/core/graph/condensation.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <functional>
#include <map>
#include <set>

#include "longterm_mapper2d/core/graph/condensation_parts.h"
#include "longterm_mapper2d/core/graph/optimizer.h"

namespace longterm_mapper2d {
namespace {

constexpr int kLocalIterations = 10;

Eigen::Matrix3d Symmetric(const Eigen::Matrix3d& m) { return 0.5 * (m + m.transpose()); }

std::vector<CondensationPart> SplitFactorSet(const PoseGraph& graph,
                                             const std::set<GraphNodeId>& removed,
                                             const std::vector<std::size_t>& factor_set,
                                             GraphNodeId gauge) {
  // Union-find over the nodes of the factor set.
  std::map<GraphNodeId, GraphNodeId> parent;
  std::function<GraphNodeId(GraphNodeId)> find = [&](GraphNodeId x) {
    if (!parent.count(x)) parent[x] = x;
    return parent[x] == x ? x : parent[x] = find(parent[x]);
  };
  for (std::size_t i : factor_set) {
    const GraphEdge& e = graph.edges()[i];
    parent[find(e.from)] = find(e.to);
  }
  std::map<GraphNodeId, CondensationPart> parts;
  for (const auto& [id, unused] : parent) {
    CondensationPart& part = parts[find(id)];
    (removed.count(id) ? part.removed : part.neighbours).push_back(id);
  }
  for (std::size_t i : factor_set) parts[find(graph.edges()[i].from)].edges.push_back(i);
  std::vector<CondensationPart> out;
  for (auto& [root, part] : parts) {
    if (part.neighbours.size() < 2) continue;  // nothing to say about the rest of the graph
    const bool has_gauge =
        std::find(part.neighbours.begin(), part.neighbours.end(), gauge) != part.neighbours.end();
    part.gauge =
        has_gauge ? gauge : *std::max_element(part.neighbours.begin(), part.neighbours.end());
    part.neighbours.erase(std::find(part.neighbours.begin(), part.neighbours.end(), part.gauge));
    out.push_back(std::move(part));
  }
  return out;
}

}  // namespace

std::optional<CondensationMode> CondensationModeFromName(const std::string& name) {
  if (name == "local_tree") return CondensationMode::kLocalTree;
  if (name == "local_star") return CondensationMode::kLocalStar;
  if (name == "whole_graph") return CondensationMode::kWholeGraph;
  return std::nullopt;
}

Eigen::MatrixXd DenseInformation(const PoseGraph& graph, const std::vector<std::size_t>& edges,
                                 const std::vector<GraphNodeId>& order) {
  std::map<GraphNodeId, int> index;
  for (std::size_t i = 0; i < order.size(); ++i) index[order[i]] = 3 * static_cast<int>(i);
  const int n = 3 * static_cast<int>(order.size());
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t k : edges) {
    const GraphEdge& e = graph.edges()[k];
    Eigen::Vector3d residual;
    Eigen::Matrix3d j_from, j_to;
    EvaluateRelativePoseResidual(graph.node(e.from).pose.vector(), graph.node(e.to).pose.vector(),
                                 e.measurement, Eigen::Matrix3d::Identity(), &residual, &j_from,
                                 &j_to);
    const std::pair<GraphNodeId, const Eigen::Matrix3d*> ends[2] = {{e.from, &j_from},
                                                                    {e.to, &j_to}};
    for (const auto& [a, ja] : ends) {
      if (!index.count(a)) continue;
      for (const auto& [b, jb] : ends) {
        if (!index.count(b)) continue;
        h.block<3, 3>(index[a], index[b]) += ja->transpose() * e.information * *jb;
      }
    }
  }
  return h;
}

Eigen::Matrix3d EdgeInformationFromNodeInformation(const Pose2& from, const Pose2& to,
                                                   const Eigen::Matrix3d& h_free, bool free_is_to) {
  Eigen::Vector3d residual;
  Eigen::Matrix3d j_from, j_to;
  EvaluateRelativePoseResidual(from.vector(), to.vector(), from.Between(to),
                               Eigen::Matrix3d::Identity(), &residual, &j_from, &j_to);
  const Eigen::Matrix3d j_inverse = (free_is_to ? j_to : j_from).inverse();
  return Symmetric(j_inverse.transpose() * h_free * j_inverse);
}

GraphEdge FuseEdges(const GraphEdge& a, const GraphEdge& b) {
  GraphEdge fused = b;
  fused.information = Symmetric(a.information + b.information);
  const Eigen::Vector3d delta_a = b.measurement.Between(a.measurement).vector();
  const Eigen::Vector3d delta = fused.information.ldlt().solve(a.information * delta_a);
  fused.measurement = b.measurement * Pose2::FromVector(delta);
  if (a.gating_information || b.gating_information) {
    fused.gating_information = Symmetric(a.gating_information.value_or(a.information) +
                                         b.gating_information.value_or(b.information));
  }
  return fused;
}

StatusOr<CondensationReport> RemoveNodesCondensed(PoseGraph& graph,
                                                  const std::vector<GraphNodeId>& removed,
                                                  GraphNodeId gauge, CondensationMode mode,
                                                  int session_id, double stamp_s) {
  const std::set<GraphNodeId> to_remove(removed.begin(), removed.end());
  if (!graph.HasNode(gauge))
    return Status::Error("gauge node " + std::to_string(gauge) + " is missing");
  if (to_remove.count(gauge)) return Status::Error("the gauge node cannot be removed");
  for (GraphNodeId id : to_remove) {
    if (!graph.HasNode(id)) return Status::Error("node " + std::to_string(id) + " is missing");
  }
  CondensationReport report;
  std::vector<std::size_t> factor_set;
  for (std::size_t i = 0; i < graph.edges().size(); ++i) {
    const GraphEdge& e = graph.edges()[i];
    if (to_remove.count(e.from) || to_remove.count(e.to)) factor_set.push_back(i);
  }
  report.removed_edges = static_cast<int>(factor_set.size());

  // Work on a copy: the linearisation point is the optimum of the factor set (local mode) or of
  // the whole graph (released mode), with the part's gauge fixed; the graph keeps its estimate.
  std::vector<GraphEdge> condensed;
  for (const CondensationPart& part : SplitFactorSet(graph, to_remove, factor_set, gauge)) {
    PoseGraph work = graph;
    OptimizerOptions options;
    options.max_iterations = kLocalIterations;
    options.loop_closure_loss_scale = 0.0;
    std::vector<Eigen::Matrix3d> h;
    std::vector<bool> valid(part.neighbours.size(), true);
    bool ok = false;
    if (mode == CondensationMode::kLocalTree) {
      Optimize(work, options, part.edges, part.gauge);
      std::vector<GraphEdge> tree;
      if (LocalTreeEdges(work, part, &tree, &report.scale)) {
        for (GraphEdge& edge : tree) {
          edge.kind = EdgeKind::kCondensed;
          edge.session_id = session_id;
          edge.stamp_s = stamp_s;
          condensed.push_back(edge);
        }
        continue;
      }
    } else if (mode == CondensationMode::kLocalStar) {
      Optimize(work, options, part.edges, part.gauge);
      ok = LocalStarMarginals(work, part, &h, &report.scale);
    } else {
      Optimize(work, options, std::nullopt, part.gauge);
      ok = WholeGraphMarginals(work, part, &h);
    }
    if (!ok) {
      work = graph;
      ComposedMarginals(work, part, &h, &valid);
    }
    for (std::size_t i = 0; i < part.neighbours.size(); ++i) {
      if (!valid[i]) {
        ++report.dropped_edges;
        continue;
      }
      GraphEdge edge;
      edge.from = part.gauge;
      edge.to = part.neighbours[i];
      edge.kind = EdgeKind::kCondensed;
      edge.session_id = session_id;
      edge.stamp_s = stamp_s;
      const Pose2& x_from = work.node(edge.from).pose;
      const Pose2& x_to = work.node(edge.to).pose;
      // Orient the edge like one that already joins the pair, so the two can fuse.
      const auto existing = graph.FindEdge(edge.from, edge.to);
      const bool reversed =
          existing && graph.edges()[*existing].from == edge.to && !to_remove.count(edge.to);
      if (reversed) {
        std::swap(edge.from, edge.to);
        edge.measurement = x_to.Between(x_from);
        edge.information = EdgeInformationFromNodeInformation(x_to, x_from, h[i], false);
      } else {
        edge.measurement = x_from.Between(x_to);
        edge.information = EdgeInformationFromNodeInformation(x_from, x_to, h[i], true);
      }
      if (!ok) ++report.composed_edges;
      condensed.push_back(edge);
    }
  }

  const bool gauge_removed = graph.gauge() && to_remove.count(*graph.gauge());
  for (GraphNodeId id : to_remove) graph.RemoveNode(id);
  report.removed_nodes = static_cast<int>(to_remove.size());
  if (gauge_removed) graph.SetGauge(gauge);
  for (const GraphEdge& edge : condensed) {
    if (const auto existing = graph.FindEdge(edge.from, edge.to)) {
      GraphEdge& old = graph.mutable_edges()[*existing];
      old = FuseEdges(old, edge);
      old.kind = EdgeKind::kCondensed;
      ++report.fused_edges;
    } else {
      if (Status s = graph.AddEdge(edge); !s.ok()) return s;
      ++report.added_edges;
    }
  }
  return report;
}

}  // namespace longterm_mapper2d
