#include "longterm_mapper2d/core/graph/condensation.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <deque>
#include <functional>
#include <map>
#include <set>

#include "longterm_mapper2d/core/graph/optimizer.h"

namespace longterm_mapper2d {
namespace {

// Relative eigenvalue below which the local system counts as rank deficient.
constexpr double kRankTolerance = 1e-10;
constexpr int kLocalIterations = 10;

Eigen::Matrix3d Symmetric(const Eigen::Matrix3d& m) { return 0.5 * (m + m.transpose()); }

bool PositiveDefinite(const Eigen::MatrixXd& m) {
  if (m.size() == 0 || !m.allFinite()) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(m, Eigen::EigenvaluesOnly);
  const double max = eig.eigenvalues().maxCoeff();
  return max > 0.0 && eig.eigenvalues().minCoeff() > kRankTolerance * max;
}

// Additive-coordinate covariance of the relative pose `z` of an edge with information `omega`:
// the error e = [R_z' dt; dtheta] of an additive increment on the `to` end, so
// P = blockdiag(R_z, 1) Omega^-1 blockdiag(R_z, 1)'.
Eigen::Matrix3d RelativeCovariance(const Pose2& z, const Eigen::Matrix3d& omega) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  r.topLeftCorner<2, 2>() = z.rotation();
  return Symmetric(r * omega.inverse() * r.transpose());
}

// Covariance of a^-1 from that of a (additive coordinates).
Eigen::Matrix3d InverseCovariance(const Pose2& a, const Eigen::Matrix3d& p) {
  const double c = std::cos(a.theta()), s = std::sin(a.theta());
  Eigen::Matrix3d j = Eigen::Matrix3d::Zero();
  j.topLeftCorner<2, 2>() = -a.rotation().transpose();
  // d(-R' t)/dtheta = -[[-s, c], [-c, -s]] t
  j(0, 2) = -(-s * a.x() + c * a.y());
  j(1, 2) = -(-c * a.x() - s * a.y());
  j(2, 2) = -1.0;
  return Symmetric(j * p * j.transpose());
}

// One connected part of the local factor set.
struct Part {
  std::vector<GraphNodeId> removed;
  std::vector<GraphNodeId> neighbours;  // remaining nodes, the part's gauge excluded
  std::vector<std::size_t> edges;
  GraphNodeId gauge = 0;
};

std::vector<Part> SplitFactorSet(const PoseGraph& graph, const std::set<GraphNodeId>& removed,
                                 const std::vector<std::size_t>& factor_set, GraphNodeId gauge) {
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
  std::map<GraphNodeId, Part> parts;
  for (const auto& [id, unused] : parent) {
    Part& part = parts[find(id)];
    (removed.count(id) ? part.removed : part.neighbours).push_back(id);
  }
  for (std::size_t i : factor_set) parts[find(graph.edges()[i].from)].edges.push_back(i);
  std::vector<Part> out;
  for (auto& [root, part] : parts) {
    if (part.neighbours.size() < 2) continue;  // nothing to say about the rest of the graph
    const bool has_gauge =
        std::find(part.neighbours.begin(), part.neighbours.end(), gauge) != part.neighbours.end();
    part.gauge = has_gauge ? gauge : *std::max_element(part.neighbours.begin(), part.neighbours.end());
    part.neighbours.erase(std::find(part.neighbours.begin(), part.neighbours.end(), part.gauge));
    out.push_back(std::move(part));
  }
  return out;
}

// The neighbours' information on their additive increments (gauge fixed), one 3x3 block each,
// from the exact Schur complement of the part, scaled by s so that blockdiag(s Sigma_ii^-1) never
// exceeds the joint information (Sigma^-1 >= s D holds for s = the smallest generalised eigenvalue
// of (Sigma^-1, D), D = blockdiag(Sigma_ii^-1); s <= 1, and s = 1 for a single neighbour).
bool LocalMarginals(const PoseGraph& graph, const Part& part, std::vector<Eigen::Matrix3d>* h,
                    double* scale) {
  std::vector<GraphNodeId> order = part.neighbours;
  order.insert(order.end(), part.removed.begin(), part.removed.end());
  const Eigen::MatrixXd information = DenseInformation(graph, part.edges, order);
  if (!PositiveDefinite(information)) return false;
  const Eigen::MatrixXd covariance =
      information.ldlt().solve(Eigen::MatrixXd::Identity(information.rows(), information.cols()));
  const int n = 3 * static_cast<int>(part.neighbours.size());
  const Eigen::MatrixXd sigma = 0.5 * (covariance.topLeftCorner(n, n) +
                                       covariance.topLeftCorner(n, n).transpose());
  if (!PositiveDefinite(sigma)) return false;
  const Eigen::MatrixXd joint = sigma.ldlt().solve(Eigen::MatrixXd::Identity(n, n));
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(n, n);
  h->clear();
  for (int i = 0; i < n; i += 3) {
    const Eigen::Matrix3d block = Symmetric(sigma.block<3, 3>(i, i).inverse());
    d.block<3, 3>(i, i) = block;
    h->push_back(block);
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(0.5 * (joint + joint.transpose()),
                                                                d, Eigen::EigenvaluesOnly);
  if (ges.info() != Eigen::Success) return false;
  *scale = std::min(1.0, ges.eigenvalues().minCoeff());
  if (!(*scale > 0.0)) return false;
  for (Eigen::Matrix3d& block : *h) block *= *scale;
  return true;
}

// The released code's marginals: each neighbour's block from the whole graph, gauge fixed.
bool WholeGraphMarginals(const PoseGraph& graph, const Part& part, std::vector<Eigen::Matrix3d>* h) {
  auto marginals = ComputeMarginals(graph, part.gauge, part.neighbours);
  if (!marginals.ok()) return false;
  h->clear();
  for (GraphNodeId id : part.neighbours) {
    const Eigen::Matrix3d& sigma = marginals.value().at(id);
    if (!PositiveDefinite(sigma)) return false;
    h->push_back(Symmetric(sigma.inverse()));
  }
  return true;
}

// The composed-path fallback: each neighbour's pose relative to the gauge composed along a
// breadth-first tree of the part, the covariance propagated through the compositions. The tree
// paths share edges, so each star edge keeps 1/k of its information (k neighbours), which bounds
// the star by the joint information (Cauchy-Schwarz). A neighbour behind a singular edge gets none.
void ComposedMarginals(const PoseGraph& graph, const Part& part, std::vector<Eigen::Matrix3d>* h,
                       std::vector<bool>* valid) {
  struct Reach {
    Pose2 gauge_T_node;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    bool valid = true;
  };
  std::map<GraphNodeId, Reach> reached{{part.gauge, Reach{}}};
  std::deque<GraphNodeId> queue{part.gauge};
  while (!queue.empty()) {
    const GraphNodeId at = queue.front();
    queue.pop_front();
    for (std::size_t i : part.edges) {
      const GraphEdge& e = graph.edges()[i];
      if (e.from != at && e.to != at) continue;
      const GraphNodeId other = e.from == at ? e.to : e.from;
      if (reached.count(other)) continue;
      Reach next;
      const Reach& here = reached.at(at);
      next.valid = here.valid && PositiveDefinite(e.information);
      Pose2 step = e.measurement;
      Eigen::Matrix3d step_covariance = Eigen::Matrix3d::Identity();
      if (next.valid) {
        step_covariance = RelativeCovariance(e.measurement, e.information);
        if (e.to == at) {
          step_covariance = InverseCovariance(e.measurement, step_covariance);
          step = e.measurement.inverse();
        }
      }
      next.gauge_T_node = here.gauge_T_node * step;
      const Eigen::Matrix3d ja = ComposeJacobianLeft(here.gauge_T_node, step);
      const Eigen::Matrix3d jb = ComposeJacobianRight(here.gauge_T_node, step);
      next.covariance = Symmetric(ja * here.covariance * ja.transpose() +
                                  jb * step_covariance * jb.transpose());
      reached[other] = next;
      queue.push_back(other);
    }
  }
  const double k = static_cast<double>(part.neighbours.size());
  Eigen::Matrix3d to_global = Eigen::Matrix3d::Identity();
  to_global.topLeftCorner<2, 2>() = graph.node(part.gauge).pose.rotation();
  h->clear();
  valid->clear();
  for (GraphNodeId id : part.neighbours) {
    const auto it = reached.find(id);
    const bool ok = it != reached.end() && it->second.valid &&
                    PositiveDefinite(it->second.covariance);
    valid->push_back(ok);
    if (!ok) {
      h->push_back(Eigen::Matrix3d::Zero());
      continue;
    }
    const Eigen::Matrix3d global = to_global * it->second.covariance * to_global.transpose();
    h->push_back(Symmetric(global.inverse()) / k);
  }
}

}  // namespace

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
  return fused;
}

StatusOr<CondensationReport> RemoveNodesCondensed(PoseGraph& graph,
                                                  const std::vector<GraphNodeId>& removed,
                                                  GraphNodeId gauge, CondensationMode mode,
                                                  int session_id, double stamp_s) {
  const std::set<GraphNodeId> to_remove(removed.begin(), removed.end());
  if (!graph.HasNode(gauge)) return Status::Error("gauge node " + std::to_string(gauge) + " is missing");
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
  for (const Part& part : SplitFactorSet(graph, to_remove, factor_set, gauge)) {
    PoseGraph work = graph;
    OptimizerOptions options;
    options.max_iterations = kLocalIterations;
    options.loop_closure_loss_scale = 0.0;
    std::vector<Eigen::Matrix3d> h;
    std::vector<bool> valid(part.neighbours.size(), true);
    bool ok = false;
    if (mode == CondensationMode::kLocal) {
      Optimize(work, options, part.edges, part.gauge);
      ok = LocalMarginals(work, part, &h, &report.scale);
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
      const bool reversed = existing && graph.edges()[*existing].from == edge.to &&
                            !to_remove.count(edge.to);
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
