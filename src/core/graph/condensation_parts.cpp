#include "longterm_mapper2d/core/graph/condensation_parts.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <tuple>

#include "longterm_mapper2d/core/graph/condensation.h"
#include "longterm_mapper2d/core/graph/optimizer.h"

namespace longterm_mapper2d {
namespace {

// Relative eigenvalue below which the local system counts as rank deficient. Small: a local
// system legitimately spans closures (information 1e3) and nodes that earlier merges left
// loosely tied (1e-7), and each part refused here falls back to composed paths, whose star keeps
// only 1/k of the information. With 1e-10, weak edges bred weaker ones until, after six hours of
// patrol, the loop closer's marginals failed and no node merged any more.
constexpr double kRankTolerance = 1e-14;

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

// The covariance of the neighbours' additive increments (gauge fixed, neighbours in part order)
// from the exact Schur complement of the part's information.
bool NeighbourCovariance(const PoseGraph& graph, const CondensationPart& part,
                         Eigen::MatrixXd* sigma) {
  std::vector<GraphNodeId> order = part.neighbours;
  order.insert(order.end(), part.removed.begin(), part.removed.end());
  const Eigen::MatrixXd information = DenseInformation(graph, part.edges, order);
  if (!PositiveDefinite(information)) return false;
  const Eigen::MatrixXd covariance =
      information.ldlt().solve(Eigen::MatrixXd::Identity(information.rows(), information.cols()));
  const int n = 3 * static_cast<int>(part.neighbours.size());
  *sigma = 0.5 * (covariance.topLeftCorner(n, n) + covariance.topLeftCorner(n, n).transpose());
  return PositiveDefinite(*sigma);
}

// The largest s <= 1 with s * approximation <= joint (both information matrices): the smallest
// generalised eigenvalue of (joint, approximation). Zero if it cannot be computed.
double ConservativeScale(const Eigen::MatrixXd& joint, const Eigen::MatrixXd& approximation) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(
      0.5 * (joint + joint.transpose()), 0.5 * (approximation + approximation.transpose()),
      Eigen::EigenvaluesOnly);
  if (ges.info() != Eigen::Success) return 0.0;
  return std::min(1.0, ges.eigenvalues().minCoeff());
}

// Orients a condensed edge between a and b like an edge that already joins the pair, so the two
// can fuse; otherwise a -> b.
std::pair<GraphNodeId, GraphNodeId> Oriented(const PoseGraph& graph, GraphNodeId a, GraphNodeId b) {
  const auto existing = graph.FindEdge(a, b);
  if (existing && graph.edges()[*existing].from == b) return {b, a};
  return {a, b};
}

// The edge from -> to at measurement from^-1 to, with the information S^-1 of its error under
// the joint covariance `sigma` of the free ends' additive increments (from's rows first; a fixed
// end has none): S = J sigma J', J the error's Jacobian with respect to the free ends (the
// closed form of the unscented labelling, ALGORITHMS.md §9.4).
GraphEdge Labelled(const Pose2& from_pose, const Pose2& to_pose, bool from_free, bool to_free,
                   const Eigen::MatrixXd& sigma) {
  Eigen::Vector3d residual;
  Eigen::Matrix3d j_from, j_to;
  EvaluateRelativePoseResidual(from_pose.vector(), to_pose.vector(), from_pose.Between(to_pose),
                               Eigen::Matrix3d::Identity(), &residual, &j_from, &j_to);
  Eigen::MatrixXd j(3, sigma.rows());
  if (from_free && to_free) {
    j << j_from, j_to;
  } else {
    j = from_free ? j_from : j_to;
  }
  GraphEdge edge;
  edge.measurement = from_pose.Between(to_pose);
  const Eigen::Matrix3d s = Symmetric(j * sigma * j.transpose());
  edge.information = Symmetric(s.inverse());
  return edge;
}

}  // namespace

// The neighbours' information on their additive increments (gauge fixed), one 3x3 block each,
// from the exact Schur complement of the part, scaled by s so that blockdiag(s Sigma_ii^-1) never
// exceeds the joint information (Sigma^-1 >= s D holds for s = the smallest generalised eigenvalue
// of (Sigma^-1, D), D = blockdiag(Sigma_ii^-1); s <= 1, and s = 1 for a single neighbour).
bool LocalStarMarginals(const PoseGraph& graph, const CondensationPart& part,
                        std::vector<Eigen::Matrix3d>* h, double* scale) {
  Eigen::MatrixXd sigma;
  if (!NeighbourCovariance(graph, part, &sigma)) return false;
  const int n = static_cast<int>(sigma.rows());
  const Eigen::MatrixXd joint = sigma.ldlt().solve(Eigen::MatrixXd::Identity(n, n));
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(n, n);
  h->clear();
  for (int i = 0; i < n; i += 3) {
    const Eigen::Matrix3d block = Symmetric(sigma.block<3, 3>(i, i).inverse());
    d.block<3, 3>(i, i) = block;
    h->push_back(block);
  }
  *scale = ConservativeScale(joint, d);
  if (!(*scale > 0.0)) return false;
  for (Eigen::Matrix3d& block : *h) block *= *scale;
  return true;
}

// The part's exact marginal kept as a spanning tree over the gauge and the neighbours instead of
// a star: the tree whose edges are the most certain relative poses under the joint marginal
// (Prim on log det of each candidate edge's error covariance), each edge labelled with that
// covariance. Where the star joins the predecessor and the successor of a removed node only
// through the loop closure (centimetres, degrees), the tree keeps their relative pose as precise
// as the tracker measured it. Scaled, like the star, so that the tree is never more confident
// than the joint marginal; a chain is kept exactly (scale 1).
bool LocalTreeEdges(const PoseGraph& graph, const CondensationPart& part,
                    std::vector<GraphEdge>* edges, double* scale) {
  Eigen::MatrixXd sigma;
  if (!NeighbourCovariance(graph, part, &sigma)) return false;
  const int k = static_cast<int>(part.neighbours.size());
  // Vertex 0 is the gauge, vertex i + 1 neighbour i.
  auto id_of = [&](int v) { return v == 0 ? part.gauge : part.neighbours[v - 1]; };
  // Joint covariance of the free ends of the edge u -> v (u's rows first).
  auto pair_covariance = [&](int u, int v) {
    if (u == 0) return Eigen::MatrixXd(sigma.block<3, 3>(3 * (v - 1), 3 * (v - 1)));
    const int rows[2] = {3 * (u - 1), 3 * (v - 1)};
    Eigen::MatrixXd c(6, 6);
    for (int a = 0; a < 2; ++a) {
      for (int b = 0; b < 2; ++b) c.block<3, 3>(3 * a, 3 * b) = sigma.block<3, 3>(rows[a], rows[b]);
    }
    return c;
  };
  // The edge u -> v labelled from the marginal; `orient` turns it like an edge that already
  // joins the pair. Orientation does not change det S (the two errors differ by a map of unit
  // determinant), so the tree is chosen on unoriented edges and only its edges are oriented.
  auto label = [&](int u, int v, bool orient) {
    GraphNodeId from = id_of(u), to = id_of(v);
    if (orient) std::tie(from, to) = Oriented(graph, from, to);
    const int f = from == id_of(u) ? u : v, t = from == id_of(u) ? v : u;
    const Eigen::MatrixXd c =
        f == 0 || t == 0 ? pair_covariance(0, f == 0 ? t : f) : pair_covariance(f, t);
    GraphEdge edge = Labelled(graph.node(from).pose, graph.node(to).pose, f != 0, t != 0, c);
    edge.from = from;
    edge.to = to;
    return edge;
  };
  // -log det of each candidate edge's information (infinite if it has none), then Prim.
  const double none = std::numeric_limits<double>::infinity();
  Eigen::MatrixXd weight = Eigen::MatrixXd::Constant(k + 1, k + 1, none);
  for (int u = 0; u <= k; ++u) {
    for (int v = std::max(u + 1, 1); v <= k; ++v) {
      const GraphEdge edge = label(u, v, false);
      if (PositiveDefinite(edge.information)) {
        weight(u, v) = weight(v, u) = -std::log(edge.information.determinant());
      }
    }
  }
  std::vector<bool> in_tree(k + 1, false);
  in_tree[0] = true;
  edges->clear();
  for (int added = 0; added < k; ++added) {
    double best = none;
    int best_u = -1, best_v = -1;
    for (int u = 0; u <= k; ++u) {
      if (!in_tree[u]) continue;
      for (int v = 1; v <= k; ++v) {
        if (!in_tree[v] && weight(u, v) < best) {
          best = weight(u, v);
          best_u = u;
          best_v = v;
        }
      }
    }
    if (best_v < 0) return false;
    in_tree[best_v] = true;
    edges->push_back(label(best_u, best_v, true));
  }
  // The tree's information on the neighbours against the joint one.
  PoseGraph tree;
  tree.AddNode(graph.node(part.gauge));
  for (GraphNodeId id : part.neighbours) tree.AddNode(graph.node(id));
  std::vector<std::size_t> all;
  for (const GraphEdge& edge : *edges) {
    if (!tree.AddEdge(edge).ok()) return false;
    all.push_back(all.size());
  }
  const int n = static_cast<int>(sigma.rows());
  const Eigen::MatrixXd joint = sigma.ldlt().solve(Eigen::MatrixXd::Identity(n, n));
  *scale = ConservativeScale(joint, DenseInformation(tree, all, part.neighbours));
  if (!(*scale > 0.0)) return false;
  for (GraphEdge& edge : *edges) edge.information *= *scale;
  return true;
}

// The released code's marginals: each neighbour's block from the whole graph, gauge fixed.
bool WholeGraphMarginals(const PoseGraph& graph, const CondensationPart& part,
                         std::vector<Eigen::Matrix3d>* h) {
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
void ComposedMarginals(const PoseGraph& graph, const CondensationPart& part,
                       std::vector<Eigen::Matrix3d>* h, std::vector<bool>* valid) {
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
      next.covariance =
          Symmetric(ja * here.covariance * ja.transpose() + jb * step_covariance * jb.transpose());
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
    const bool ok =
        it != reached.end() && it->second.valid && PositiveDefinite(it->second.covariance);
    valid->push_back(ok);
    if (!ok) {
      h->push_back(Eigen::Matrix3d::Zero());
      continue;
    }
    const Eigen::Matrix3d global = to_global * it->second.covariance * to_global.transpose();
    h->push_back(Symmetric(global.inverse()) / k);
  }
}

}  // namespace longterm_mapper2d
