#include "longterm_mapper2d/core/graph/condensation.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cstdio>
#include <random>
#include <set>

#include "longterm_mapper2d/core/graph/optimizer.h"

namespace longterm_mapper2d {
namespace {

// Graphs whose measurements agree with the node poses, so every optimum is the current estimate
// and the exact marginal is the Schur complement at that point.
class RandomGraph {
 public:
  explicit RandomGraph(int nodes, unsigned seed) : rng_(seed) {
    std::uniform_real_distribution<double> xy(-5.0, 5.0), th(-M_PI, M_PI);
    for (int i = 0; i < nodes; ++i) {
      GraphNode n;
      n.id = i;
      n.pose = Pose2(xy(rng_), xy(rng_), th(rng_));
      EXPECT_TRUE(graph.AddNode(n).ok());
    }
  }
  void Connect(GraphNodeId a, GraphNodeId b, EdgeKind kind = EdgeKind::kOdometry) {
    std::uniform_real_distribution<double> u(-1.0, 1.0), scale(20.0, 400.0);
    Eigen::Matrix3d m = Eigen::Matrix3d::Random();
    GraphEdge e;
    e.from = a;
    e.to = b;
    e.measurement = graph.node(a).pose.Between(graph.node(b).pose);
    e.information = m * m.transpose() * scale(rng_) + 5.0 * Eigen::Matrix3d::Identity();
    e.kind = kind;
    EXPECT_TRUE(graph.AddEdge(e).ok());
  }
  PoseGraph graph;

 private:
  std::mt19937 rng_;
};

Eigen::MatrixXd Covariance(const PoseGraph& graph, const std::vector<GraphNodeId>& order) {
  std::vector<std::size_t> all(graph.edges().size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  const Eigen::MatrixXd h = DenseInformation(graph, all, order);
  return h.inverse();
}

// Condenses `removed` into `gauge` and compares the covariance of the remaining nodes (relative
// to `reference`) with exact marginalisation; returns trace(condensed) / trace(exact).
double CheckAgainstExact(PoseGraph graph, const std::vector<GraphNodeId>& removed,
                         GraphNodeId gauge, GraphNodeId reference,
                         CondensationMode mode = CondensationMode::kLocalTree,
                         double relative_tolerance = 1e-9) {
  const std::set<GraphNodeId> gone(removed.begin(), removed.end());
  std::vector<GraphNodeId> kept, all;
  for (const auto& [id, n] : graph.nodes()) {
    if (id == reference) continue;
    all.push_back(id);
    if (!gone.count(id)) kept.push_back(id);
  }
  // Exact: all nodes, then the kept ones' block of the covariance (Schur complement of the rest).
  std::vector<GraphNodeId> order = kept;
  for (GraphNodeId id : all) {
    if (gone.count(id)) order.push_back(id);
  }
  const Eigen::MatrixXd exact_full = Covariance(graph, order);
  const int n = 3 * static_cast<int>(kept.size());
  const Eigen::MatrixXd exact = exact_full.topLeftCorner(n, n);

  auto report = RemoveNodesCondensed(graph, removed, gauge, mode, 1, 10.0);
  EXPECT_TRUE(report.ok()) << report.status().message();
  for (GraphNodeId id : removed) EXPECT_FALSE(graph.HasNode(id));
  // No pair joined twice, and every condensed edge agrees with the poses.
  std::set<std::pair<GraphNodeId, GraphNodeId>> pairs;
  for (const GraphEdge& e : graph.edges()) {
    EXPECT_TRUE(pairs.insert({std::min(e.from, e.to), std::max(e.from, e.to)}).second)
        << e.from << "-" << e.to;
    EXPECT_LT(EdgeChi2(graph, e), 1e-12);
  }
  const Eigen::MatrixXd condensed = Covariance(graph, kept);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> difference(condensed - exact);
  const double size = exact.diagonal().maxCoeff();
  EXPECT_GT(difference.eigenvalues().minCoeff(), -relative_tolerance * size)
      << "the condensed graph is more confident than exact marginalisation";
  return condensed.trace() / exact.trace();
}

TEST(Condensation, ChainIsExact) {
  RandomGraph g(6, 1);
  for (int i = 0; i + 1 < 6; ++i) g.Connect(i, i + 1);
  // One neighbour besides the gauge: the star is the exact marginal.
  EXPECT_NEAR(CheckAgainstExact(g.graph, {2}, 3, 0), 1.0, 1e-6);
}

TEST(Condensation, NeverMoreConfidentThanExactMarginalisation) {
  // Adversarial: neighbours scattered 10 m around the removed node, random anisotropic
  // information. Neither a tree nor a star keeps every correlation, so both must be loose here.
  for (CondensationMode mode : {CondensationMode::kLocalTree, CondensationMode::kLocalStar}) {
    for (unsigned seed = 0; seed < 20; ++seed) {
      RandomGraph g(8, seed);
      for (int leaf = 1; leaf < 8; ++leaf) g.Connect(0, leaf);
      g.Connect(1, 2);
      g.Connect(3, 4);
      EXPECT_GE(CheckAgainstExact(g.graph, {0}, 7, 1, mode), 1.0 - 1e-9) << "seed " << seed;
    }
    for (unsigned seed = 0; seed < 20; ++seed) {
      RandomGraph g(10, 100 + seed);
      for (int i = 0; i + 1 < 10; ++i) g.Connect(i, i + 1);
      g.Connect(9, 2, EdgeKind::kLoopClosure);
      g.Connect(8, 3, EdgeKind::kLoopClosure);
      CheckAgainstExact(g.graph, {2}, 9, 0, mode);
      CheckAgainstExact(g.graph, {2, 3}, 9, 0, mode);
    }
  }
}

// What maintenance removes: a robot drives around a 10 m square (a node every 2.5 m, odometry
// edges), comes back past its start, and the new nodes close on the old ones in the same places.
PoseGraph Revisit(int laps_nodes, int first_revisited, double offset_m) {
  PoseGraph graph;
  auto pose_at = [](int k) {
    const int side = (k / 4) % 4, step = k % 4;
    const double s = 2.5 * step;
    const Pose2 corners[4] = {Pose2(0, 0, 0), Pose2(10, 0, M_PI / 2), Pose2(10, 10, M_PI),
                              Pose2(0, 10, -M_PI / 2)};
    return corners[side] * Pose2(s, 0.0, 0.0);
  };
  for (int k = 0; k < laps_nodes; ++k) {
    GraphNode n;
    n.id = k;
    n.pose = pose_at(k) * Pose2(k >= 16 ? offset_m : 0.0, 0.0, 0.0);
    EXPECT_TRUE(graph.AddNode(n).ok());
  }
  auto connect = [&graph](GraphNodeId a, GraphNodeId b, const Eigen::Vector3d& information,
                          EdgeKind kind) {
    GraphEdge e;
    e.from = a;
    e.to = b;
    e.measurement = graph.node(a).pose.Between(graph.node(b).pose);
    e.information = information.asDiagonal();
    e.kind = kind;
    EXPECT_TRUE(graph.AddEdge(e).ok());
  };
  for (int k = 0; k + 1 < laps_nodes; ++k) {
    connect(k, k + 1, Eigen::Vector3d(400.0, 1600.0, 900.0), EdgeKind::kOdometry);
  }
  for (int k = 16 + first_revisited; k < laps_nodes; ++k) {
    connect(k, k - 16, Eigen::Vector3d(1000.0, 1000.0, 300.0), EdgeKind::kLoopClosure);
  }
  return graph;
}

TEST(Condensation, RemovingRevisitedNodesIsCloseToExact) {
  const PoseGraph graph = Revisit(24, 2, 0.3);
  // The first revisit: node 18 closes on node 2. A star (edges 18-1, 18-3) keeps the relative pose
  // of 1 and 3 only through the closure; the tree keeps the edge 1-3 as the odometry made it.
  const double tree = CheckAgainstExact(graph, {2}, 18, 0, CondensationMode::kLocalTree);
  const double star = CheckAgainstExact(graph, {2}, 18, 0, CondensationMode::kLocalStar);
  EXPECT_LT(tree, 1.2);  // measured 1.11
  EXPECT_LT(star, 3.5);  // measured 2.98
  // A whole stretch merged at once.
  const double stretch = CheckAgainstExact(graph, {4, 5}, 21, 0, CondensationMode::kLocalTree);
  const double stretch_star = CheckAgainstExact(graph, {4, 5}, 21, 0, CondensationMode::kLocalStar);
  EXPECT_LT(stretch, 1.2);
  EXPECT_LT(stretch_star, 1.2);
  std::printf(
      "covariance trace ratio condensed / exact, one node: tree %.3f, star %.3f; "
      "two: tree %.3f, star %.3f\n",
      tree, star, stretch, stretch_star);
}

TEST(Condensation, ExistingEdgeIsFusedNotDuplicated) {
  RandomGraph g(5, 7);
  for (int i = 0; i + 1 < 5; ++i) g.Connect(i, i + 1);
  g.Connect(4, 2, EdgeKind::kLoopClosure);
  g.Connect(1, 4, EdgeKind::kLoopClosure);  // 1 already joins the gauge 4
  PoseGraph copy = g.graph;
  auto report = RemoveNodesCondensed(copy, {2}, 4, CondensationMode::kLocalStar, 1, 0.0);
  ASSERT_TRUE(report.ok());
  EXPECT_EQ(report.value().fused_edges, 2);  // 1 -> 4 and the odometry edge 3 -> 4
  const auto edge = copy.FindEdge(1, 4);
  ASSERT_TRUE(edge);
  EXPECT_EQ(copy.edges()[*edge].kind, EdgeKind::kCondensed);
  EXPECT_EQ(copy.edges()[*edge].from, 1);  // kept the existing orientation
  CheckAgainstExact(g.graph, {2}, 4, 0);
}

TEST(Condensation, NeighbourNotReachingTheGaugeGetsItsOwnStar) {
  RandomGraph g(9, 3);
  for (int i = 0; i + 1 < 9; ++i) g.Connect(i, i + 1);
  g.Connect(8, 2, EdgeKind::kLoopClosure);
  // Node 6 is removed too, but touches neither the gauge 8 nor node 2: its neighbours 5 and 7
  // form a part of their own, condensed into one edge 7 -> 5.
  PoseGraph copy = g.graph;
  auto report = RemoveNodesCondensed(copy, {2, 6}, 8, CondensationMode::kLocalStar, 1, 0.0);
  ASSERT_TRUE(report.ok());
  EXPECT_TRUE(copy.FindEdge(7, 5));
  CheckAgainstExact(g.graph, {2, 6}, 8, 0);
}

TEST(Condensation, SingularLocalSystemFallsBackToComposedPaths) {
  RandomGraph g(5, 11);
  for (int i = 0; i + 1 < 5; ++i) g.Connect(i, i + 1);
  g.Connect(4, 2, EdgeKind::kLoopClosure);
  // A second removed node hanging off 2 by an edge without rotation information: the local
  // system is singular.
  GraphNode extra;
  extra.id = 5;
  extra.pose = Pose2(1.0, 2.0, 0.3);
  ASSERT_TRUE(g.graph.AddNode(extra).ok());
  g.Connect(2, 5);
  g.graph.mutable_edges().back().information = Eigen::Vector3d(10.0, 10.0, 0.0).asDiagonal();
  PoseGraph copy = g.graph;
  auto report = RemoveNodesCondensed(copy, {2, 5}, 4, CondensationMode::kLocalStar, 1, 0.0);
  ASSERT_TRUE(report.ok());
  EXPECT_GT(report.value().composed_edges, 0);
  EXPECT_TRUE(copy.FindEdge(4, 1) || copy.FindEdge(1, 4));
  for (const GraphEdge& e : copy.edges()) EXPECT_TRUE(e.information.allFinite());
}

TEST(Condensation, LooselyTiedNeighbourIsStillMarginalisedExactly) {
  // After hours of merging, a local system spans closures (information 1e3) and a neighbour
  // that earlier merges left loosely tied (1e-8): ill-conditioned, not rank deficient. It must
  // be marginalised, not sent to the composed-path fallback (whose 1/k star made weak edges
  // weaker merge after merge).
  RandomGraph g(5, 13);
  for (int i = 0; i + 1 < 5; ++i) g.Connect(i, i + 1);
  g.Connect(4, 2, EdgeKind::kLoopClosure);
  for (GraphEdge& e : g.graph.mutable_edges()) {
    e.information = (e.from == 1 && e.to == 2 ? 1e-8 : 1e3) * Eigen::Matrix3d::Identity();
  }
  PoseGraph copy = g.graph;
  auto report = RemoveNodesCondensed(copy, {2}, 4, CondensationMode::kLocalTree, 1, 0.0);
  ASSERT_TRUE(report.ok());
  EXPECT_EQ(report.value().composed_edges, 0);
  // Covariances span 1e-3 to 1e9 here: compared to 1e-5 of the largest (double precision on a
  // condition number of 1e12).
  CheckAgainstExact(g.graph, {2}, 4, 0, CondensationMode::kLocalTree, 1e-5);
}

TEST(Condensation, RemovedGaugeMovesToTheSurvivor) {
  RandomGraph g(4, 5);
  for (int i = 0; i + 1 < 4; ++i) g.Connect(i, i + 1);
  g.Connect(3, 0, EdgeKind::kLoopClosure);
  ASSERT_EQ(*g.graph.gauge(), 0);
  auto report = RemoveNodesCondensed(g.graph, {0}, 3, CondensationMode::kLocalStar, 1, 0.0);
  ASSERT_TRUE(report.ok());
  EXPECT_EQ(*g.graph.gauge(), 3);
}

TEST(Condensation, WholeGraphModeKeepsEveryNeighbourConnected) {
  RandomGraph g(8, 9);
  for (int i = 0; i + 1 < 8; ++i) g.Connect(i, i + 1);
  g.Connect(7, 2, EdgeKind::kLoopClosure);
  auto report = RemoveNodesCondensed(g.graph, {2}, 7, CondensationMode::kWholeGraph, 1, 0.0);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_TRUE(g.graph.FindEdge(7, 1));
  EXPECT_TRUE(g.graph.FindEdge(7, 3));
}

TEST(Condensation, RefusesBadRequests) {
  RandomGraph g(3, 2);
  g.Connect(0, 1);
  g.Connect(1, 2);
  EXPECT_FALSE(RemoveNodesCondensed(g.graph, {1}, 1, CondensationMode::kLocalStar, 0, 0.0).ok());
  EXPECT_FALSE(RemoveNodesCondensed(g.graph, {9}, 2, CondensationMode::kLocalStar, 0, 0.0).ok());
  EXPECT_EQ(g.graph.nodes().size(), 3u);
}

TEST(Condensation, FusedEdgeIsTheInformationWeightedMean) {
  GraphEdge a, b;
  a.measurement = Pose2(1.0, 0.0, 0.0);
  b.measurement = Pose2(1.2, 0.0, 0.0);
  a.information = Eigen::Matrix3d::Identity() * 3.0;
  b.information = Eigen::Matrix3d::Identity();
  const GraphEdge f = FuseEdges(a, b);
  EXPECT_NEAR(f.measurement.x(), 1.05, 1e-9);
  EXPECT_NEAR(f.information(0, 0), 4.0, 1e-12);
  EXPECT_FALSE(f.gating_information.has_value());
  // Gating informations add too; an edge without one gates with its information.
  a.gating_information = Eigen::Matrix3d::Identity() * 0.5;
  const GraphEdge g = FuseEdges(a, b);
  ASSERT_TRUE(g.gating_information.has_value());
  EXPECT_NEAR((*g.gating_information)(0, 0), 1.5, 1e-12);
  EXPECT_NEAR(g.information(0, 0), 4.0, 1e-12);
}

}  // namespace
}  // namespace longterm_mapper2d
