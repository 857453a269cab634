// The final sweep of LoopCloser (SweepFrom and the rigid vote on its candidates).
#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "longterm_mapper2d/core/loop_closing/loop_closer.h"
#include "testing/pose_graphs.h"
#include "testing/synthetic_scans.h"

namespace longterm_mapper2d {
namespace {

using test_support::CloudSeenFrom;
using test_support::NodesAt;

// Nodes 10 and 11 came back to the room of old nodes 0 and 1 after a long way round (the chain
// 0 - 6 - 1 - 5 - 10 - 11 runs through nodes 20 m away); the graph has them `offset` from where
// their clouds were taken.
struct Revisit {
  std::map<GraphNodeId, Pose2> truth = {{0, Pose2(0.0, 0.0, 0.0)},
                                        {1, Pose2(1.0, 0.5, 0.2)},
                                        {10, Pose2(0.5, 0.3, 0.1)},
                                        {11, Pose2(0.8, -0.4, -0.2)}};
  std::map<GraphNodeId, Cloud> clouds;
  PoseGraph graph;

  explicit Revisit(const Pose2& offset) {
    const auto room = test_support::IrregularRoom();
    std::map<GraphNodeId, Pose2> in_graph = {{5, Pose2(20.0, 0.0, 0.0)},
                                             {6, Pose2(0.0, 20.0, 0.0)}};
    for (const auto& [id, pose] : truth) {
      in_graph[id] = id >= 10 ? offset * pose : pose;
      clouds[id] = CloudSeenFrom(room, pose, 8.0);
    }
    graph = test_support::OdometryGraph(in_graph, {{0, 6}, {6, 1}, {1, 5}, {5, 10}, {10, 11}},
                                        Eigen::Vector3d(3.0, 3.0, 1e3));
  }
  void Link(GraphNodeId from, GraphNodeId to, EdgeKind kind) {
    GraphEdge edge;
    edge.from = from;
    edge.to = to;
    edge.measurement = graph.node(from).pose.Between(graph.node(to).pose);
    edge.information = Eigen::Vector3d(3.0, 3.0, 1e3).asDiagonal();
    edge.kind = kind;
    EXPECT_TRUE(graph.AddEdge(edge).ok());
  }
  LoopCloser::CloudOf cloud_of() const {
    return [this](GraphNodeId id) -> const Cloud& { return clouds.at(id); };
  }
};

TEST(LoopCloserSweep, ClosesARevisitTheOptimisedGraphNowPutsWithinReach) {
  const Revisit revisit(Pose2(0.6, 0.2, 0.02));
  LoopCloser closer(LoopClosingOptions{}, RegistrationOptions{});
  MapperStats stats;
  closer.SweepFrom(revisit.graph, 10, revisit.cloud_of(), stats);
  closer.SweepFrom(revisit.graph, 11, revisit.cloud_of(), stats);
  // 0 and 1 are apart in the graph (20 m round node 6): each is aligned from each new node.
  EXPECT_EQ(stats.counters["loop_closure_alignments"], 4u);
  const std::vector<GraphEdge> accepted = closer.Vote(revisit.graph, true, stats);
  ASSERT_EQ(accepted.size(), 4u);
  for (const GraphEdge& edge : accepted) {
    EXPECT_EQ(edge.kind, EdgeKind::kLoopClosure);
    const Pose2 truth = revisit.truth.at(edge.from).Between(revisit.truth.at(edge.to));
    EXPECT_LT((edge.measurement.translation() - truth.translation()).norm(), 0.02);
    EXPECT_LT(std::abs(NormalizeAngle(edge.measurement.theta() - truth.theta())), 0.01);
  }
}

TEST(LoopCloserSweep, LooksOnlyAtOlderNodesTheGraphDoesNotAlreadyTieClosely) {
  Revisit revisit(Pose2(0.6, 0.2, 0.02));
  MapperStats stats;
  LoopCloser from_old(LoopClosingOptions{}, RegistrationOptions{});
  from_old.SweepFrom(revisit.graph, 0, revisit.cloud_of(), stats);  // 1, 10 and 11 are newer
  EXPECT_EQ(stats.counters["loop_closure_alignments"], 0u);
  // A closure already ties 10 to 1; node 0 is still 40 m away along the graph's edges.
  revisit.Link(10, 1, EdgeKind::kLoopClosure);
  LoopCloser closer(LoopClosingOptions{}, RegistrationOptions{});
  closer.SweepFrom(revisit.graph, 10, revisit.cloud_of(), stats);
  EXPECT_EQ(stats.counters["loop_closure_alignments"], 1u);
  ASSERT_EQ(closer.buffer().size(), 1u);
  EXPECT_EQ(closer.buffer().front().old, 0);
  EXPECT_TRUE(closer.buffer().front().from_sweep);
  // The search from a new node does not care how the graph already ties them.
  LoopCloser search(LoopClosingOptions{}, RegistrationOptions{});
  search.SearchFrom(revisit.graph, 10, revisit.cloud_of(), stats);
  EXPECT_EQ(stats.counters["loop_closure_alignments"], 3u);
}

TEST(LoopCloserSweep, AnAlignmentFarFromTheOptimisedGraphIsNotKept) {
  // The graph has the revisit 1.5 m off: after all its loops, the sweep does not believe that.
  const Revisit revisit(Pose2(1.5, 0.0, 0.0));
  MapperStats stats;
  LoopCloser closer(LoopClosingOptions{}, RegistrationOptions{});
  closer.SweepFrom(revisit.graph, 10, revisit.cloud_of(), stats);
  EXPECT_TRUE(closer.buffer().empty());
  EXPECT_EQ(stats.counters["loop_closure_sweep_alignments_off_graph"], 2u);
  LoopClosingOptions lenient;
  lenient.final_sweep_max_offset_m = 2.0;
  LoopCloser wider(lenient, RegistrationOptions{});
  wider.SweepFrom(revisit.graph, 10, revisit.cloud_of(), stats);
  EXPECT_EQ(wider.buffer().size(), 2u);
}

TEST(LoopCloserSweep, SweptCandidatesMustAgreeRigidly) {
  // Two revisits 10 m apart ask for corrections 0.3 m apart. New nodes voting on a drifting
  // graph allow for that much drift over 20 m; on the optimised graph they contradict each other.
  const PoseGraph graph = NodesAt({{0, Pose2(0.0, 0.0, 0.0)},
                                   {1, Pose2(10.0, 0.0, 0.0)},
                                   {10, Pose2(0.0, 1.0, 0.0)},
                                   {11, Pose2(10.0, 1.0, 0.0)}});
  const Pose2 truth_10(0.3, 1.0, 0.0), truth_11(10.6, 1.0, 0.0);
  for (const bool sweep : {false, true}) {
    LoopCloser closer(LoopClosingOptions{}, RegistrationOptions{});
    closer.AddCandidate({10, 0, truth_10.Between(graph.node(0).pose), false, sweep});
    closer.AddCandidate({11, 1, truth_11.Between(graph.node(1).pose), false, sweep});
    MapperStats stats;
    EXPECT_EQ(closer.Vote(graph, true, stats).size(), sweep ? 0u : 2u) << "sweep " << sweep;
  }
}

}  // namespace
}  // namespace longterm_mapper2d
