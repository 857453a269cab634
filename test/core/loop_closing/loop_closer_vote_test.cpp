#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <utility>
#include <vector>

#include "longterm_mapper2d/core/loop_closing/loop_closer.h"
#include "testing/pose_graphs.h"

// The vote of LoopCloser (loop_closer_vote.cpp): which buffered candidates become closures.
namespace longterm_mapper2d {
namespace {

using test_support::NodesAt;

// Old nodes 0..5 along a line; the robot comes back (nodes 10..15) with a rigid drift.
PoseGraph Revisit() {
  PoseGraph graph;
  for (int i = 0; i <= 5; ++i) {
    GraphNode old_node;
    old_node.id = i;
    old_node.pose = Pose2(2.0 * i, 0.0, 0.0);
    graph.AddNode(old_node);
    GraphNode new_node;
    new_node.id = 10 + i;
    new_node.pose = Pose2(0.5, 0.3, 0.05) * old_node.pose;
    graph.AddNode(new_node);
  }
  return graph;
}

TEST(LoopCloser, VotingAcceptsTheConsistentClosuresAndRejectsAWrongOne) {
  PoseGraph graph = Revisit();
  LoopClosingOptions options;
  options.vote_min_inliers = 3;
  LoopCloser closer(options, RegistrationOptions{});
  MapperStats stats;
  // True closures: new node 10+i is at old node i.
  for (int i = 1; i <= 4; ++i) closer.AddCandidate({10 + i, i, Pose2()});
  // A wrong one: node 15 matched to node 1 (a similar-looking place 8 m away).
  closer.AddCandidate({15, 1, Pose2(0.1, 0.0, 0.0)});
  const std::vector<GraphEdge> accepted = closer.Vote(graph, true, stats);
  ASSERT_EQ(accepted.size(), 4u);
  for (const GraphEdge& edge : accepted) {
    EXPECT_EQ(edge.from, edge.to + 10);
    EXPECT_EQ(edge.kind, EdgeKind::kLoopClosure);
  }
  EXPECT_EQ(stats.counters["loop_closures_rejected"], 1u);
  // An accepted pair is never accepted twice.
  for (int i = 1; i <= 4; ++i) closer.AddCandidate({10 + i, i, Pose2()});
  EXPECT_TRUE(closer.Vote(graph, true, stats).empty());
}

TEST(LoopCloser, TooFewAgreeingCandidatesWaitAndExpire) {
  PoseGraph graph = Revisit();
  LoopClosingOptions options;
  options.vote_min_inliers = 3;
  options.vote_window = 2;
  LoopCloser closer(options, RegistrationOptions{});
  MapperStats stats;
  closer.AddCandidate({11, 1, Pose2()});
  closer.AddCandidate({12, 2, Pose2()});
  EXPECT_TRUE(closer.Vote(graph, false, stats).empty());
  EXPECT_EQ(closer.buffer().size(), 2u);
  EXPECT_TRUE(closer.Vote(graph, false, stats).empty());
  EXPECT_TRUE(closer.buffer().empty());
  EXPECT_EQ(stats.counters["loop_closures_expired"], 2u);
}

TEST(LoopCloser, CandidatesAgainstOneOldLocalMapAreOnePieceOfEvidence) {
  // Two new nodes aligned to the same old node agree with each other even when that node is a
  // look-alike room elsewhere: with distinct-node support they do not make a closure alone.
  PoseGraph graph = Revisit();
  LoopClosingOptions options;  // vote_min_inliers 2
  MapperStats stats;
  // New node 11 is truly at old node 1; both candidates claim it is at old node 3.
  LoopCloser strict(options, RegistrationOptions{});
  strict.AddCandidate({11, 3, Pose2()});
  strict.AddCandidate({12, 3, Pose2(-2.0, 0.0, 0.0)});
  EXPECT_TRUE(strict.Vote(graph, true, stats).empty());
  // A second old node agreeing with them makes two distinct pieces on each side.
  LoopCloser supported(options, RegistrationOptions{});
  supported.AddCandidate({11, 3, Pose2()});
  supported.AddCandidate({12, 3, Pose2(-2.0, 0.0, 0.0)});
  supported.AddCandidate({12, 4, Pose2()});
  EXPECT_EQ(supported.Vote(graph, true, stats).size(), 3u);
  // Counting candidates instead (the released code's rule) accepts the pair alone.
  options.vote_distinct_nodes = false;
  LoopCloser counting(options, RegistrationOptions{});
  counting.AddCandidate({11, 3, Pose2()});
  counting.AddCandidate({12, 3, Pose2(-2.0, 0.0, 0.0)});
  EXPECT_EQ(counting.Vote(graph, true, stats).size(), 2u);
}

TEST(LoopCloser, CandidatesAgreeUpToTheDriftBetweenThem) {
  // The new trajectory bent by 0.3 m over the 8 m between nodes 11 and 15 (a drifting corridor):
  // the rigid test alone (drift 0) splits the two true closures, the drift-aware one keeps them.
  PoseGraph graph = Revisit();
  const Pose2 bent(0.0, 0.3, 0.0);
  LoopClosingOptions options;
  MapperStats stats;
  options.vote_drift_per_m = 0.0;
  options.vote_drift_rad_per_m = 0.0;
  LoopCloser rigid(options, RegistrationOptions{});
  rigid.AddCandidate({11, 1, Pose2()});
  rigid.AddCandidate({15, 5, bent});
  EXPECT_TRUE(rigid.Vote(graph, true, stats).empty());
  options.vote_drift_per_m = 0.05;
  options.vote_drift_rad_per_m = 0.01;
  LoopCloser drifting(options, RegistrationOptions{});
  drifting.AddCandidate({11, 1, Pose2()});
  drifting.AddCandidate({15, 5, bent});
  EXPECT_EQ(drifting.Vote(graph, true, stats).size(), 2u);
  // A place 6 m off is not drift: still no closure.
  LoopCloser wrong(options, RegistrationOptions{});
  wrong.AddCandidate({11, 1, Pose2()});
  wrong.AddCandidate({15, 2, Pose2()});
  EXPECT_TRUE(wrong.Vote(graph, true, stats).empty());
}

// One forced vote of a new closer over the candidates `add` buffers.
std::vector<GraphEdge> VoteOnce(const LoopClosingOptions& options, const PoseGraph& graph,
                                const std::function<void(LoopCloser&)>& add, MapperStats& stats) {
  LoopCloser closer(options, RegistrationOptions{});
  add(closer);
  return closer.Vote(graph, true, stats);
}

TEST(LoopCloser, ShortLoopsAlongTheChainDoNotOutvoteAReturnToAnOldPlace) {
  // New nodes 11-14 have drifted 3 m from where they truly are (old nodes 1-4, from long
  // ago). Each also closes a short loop with a chain node 5-8 a metre beside it, a few nodes
  // back: right, and consistent with the graph as it is. The vote moves only the waiting nodes,
  // so the short loops disagree with the return, and four of them outvote its three.
  std::map<GraphNodeId, Pose2> poses;
  const Pose2 drift(3.0, 1.0, 0.1);
  for (int i = 1; i <= 4; ++i) {
    poses[i] = Pose2(2.0 * i, 0.0, 0.0);
    poses[10 + i] = drift * poses[i];
    poses[4 + i] = poses[10 + i] * Pose2(0.0, 1.0, 0.0);
  }
  const PoseGraph graph = NodesAt(poses);
  auto add_candidates = [&](LoopCloser& closer) {
    for (int i = 1; i <= 3; ++i) closer.AddCandidate({10 + i, i, Pose2(), false});
    for (int i = 1; i <= 4; ++i) {
      closer.AddCandidate({10 + i, 4 + i, poses[10 + i].Between(poses[4 + i]), true});
    }
  };
  LoopClosingOptions options;
  MapperStats stats;
  options.vote_chain_apart = false;
  const std::vector<GraphEdge> short_only = VoteOnce(options, graph, add_candidates, stats);
  ASSERT_EQ(short_only.size(), 4u);
  for (const GraphEdge& edge : short_only) EXPECT_EQ(edge.to, edge.from - 6);
  EXPECT_EQ(stats.counters["loop_closures_rejected"], 3u);  // the return is lost
  // Voted apart, each group decides its own: the return and the short loops are all accepted.
  options.vote_chain_apart = true;
  const std::vector<GraphEdge> accepted = VoteOnce(options, graph, add_candidates, stats);
  ASSERT_EQ(accepted.size(), 7u);
  int returns = 0;
  for (const GraphEdge& edge : accepted) returns += edge.to == edge.from - 10;
  EXPECT_EQ(returns, 3);
}

TEST(LoopCloser, AHypothesisTheGraphAgreesWithRanksAboveALookAlikeOfEqualSupport) {
  // Four new nodes aligned to old node 3 where the graph already has them (one distinct old
  // node: support 1), and two of them also to a look-alike pair of rooms, 7 and 8, that would
  // move the sub-map 1 m (support 2).
  const std::map<GraphNodeId, Pose2> poses = {
      {3, Pose2(6.0, 0.0, 0.0)},  {7, Pose2(8.0, 2.0, 0.0)},  {8, Pose2(10.0, 2.0, 0.0)},
      {11, Pose2(3.0, 1.0, 0.3)}, {12, Pose2(5.0, 1.0, 0.6)}, {13, Pose2(7.0, 1.0, 0.9)},
      {14, Pose2(9.0, 1.0, 1.2)}};
  const PoseGraph graph = NodesAt(poses);
  const Pose2 shift(1.0, 0.0, 0.0);
  auto add_candidates = [&](LoopCloser& closer) {
    for (GraphNodeId id = 11; id <= 14; ++id) {
      closer.AddCandidate({id, 3, poses.at(id).Between(poses.at(3))});
    }
    closer.AddCandidate({13, 7, (shift * poses.at(13)).Between(poses.at(7))});
    closer.AddCandidate({14, 8, (shift * poses.at(14)).Between(poses.at(8))});
  };
  LoopClosingOptions options;
  MapperStats stats;
  options.vote_graph_supports = false;
  const std::vector<GraphEdge> look_alike = VoteOnce(options, graph, add_candidates, stats);
  ASSERT_EQ(look_alike.size(), 2u);
  EXPECT_EQ(look_alike[0].to, 7);
  // Counting the graph as a supporter, the graph's hypothesis ranks first (2 against 2, more
  // candidates agreeing); it is not accepted with one distinct old node, and neither is the
  // look-alike.
  options.vote_graph_supports = true;
  LoopCloser supported(options, RegistrationOptions{});
  add_candidates(supported);
  EXPECT_TRUE(supported.Vote(graph, false, stats).empty());
  EXPECT_EQ(supported.buffer().size(), 6u);
  // A second old node the graph agrees with settles it: the graph's closures are accepted, the
  // look-alike ones dropped.
  GraphNode next;
  next.id = 4;
  next.pose = Pose2(8.0, 0.0, 0.0);
  PoseGraph grown = graph;
  ASSERT_TRUE(grown.AddNode(next).ok());
  supported.AddCandidate({14, 4, poses.at(14).Between(next.pose)});
  const std::vector<GraphEdge> accepted = supported.Vote(grown, true, stats);
  ASSERT_EQ(accepted.size(), 5u);
  for (const GraphEdge& edge : accepted) EXPECT_TRUE(edge.to == 3 || edge.to == 4);
}

TEST(LoopCloser, AClosureBetweenTwoWaitingNodesIsNoEvidenceForAReturn) {
  // New nodes 11-14 are right where the graph has them (old nodes 1-4 below them, 2 m apart,
  // from long ago). Node 14 closes a short loop with node 12, which waits for its own vote too
  // (its candidate against old node 5 is wrong): right, and the graph agrees. Node 13 aligned
  // with old node 1, a look-alike 4 m back. A return moves the waiting nodes rigidly, so
  // 14 -> 12 agrees with every return as well as with the graph: counted, it was the second
  // distinct node behind the wrong one.
  std::map<GraphNodeId, Pose2> poses;
  for (int i = 1; i <= 5; ++i) poses[i] = Pose2(2.0 * i, -1.0, 0.0);
  for (int i = 1; i <= 4; ++i) poses[10 + i] = Pose2(2.0 * i, 0.0, 0.0);
  const PoseGraph graph = NodesAt(poses);
  const Pose2 look_alike = poses.at(13).Between(poses.at(3)) * Pose2(4.0, 0.0, 0.0);
  auto add_candidates = [&](LoopCloser& closer) {
    closer.AddCandidate({14, 12, poses.at(14).Between(poses.at(12))});
    closer.AddCandidate({13, 1, look_alike * poses.at(3).Between(poses.at(1))});
    closer.AddCandidate({12, 5, Pose2(-1.0, 5.0, 2.0)});
  };
  MapperStats stats;
  const std::vector<GraphEdge> accepted =
      VoteOnce(LoopClosingOptions{}, graph, add_candidates, stats);
  for (const GraphEdge& edge : accepted) {
    EXPECT_FALSE(edge.to == 1 || edge.to == 5) << edge.from << " -> " << edge.to;
  }
  EXPECT_TRUE(accepted.empty());
  // A right return of two distinct nodes is accepted, and the short loop with it.
  auto add_return = [&](LoopCloser& closer) {
    closer.AddCandidate({14, 12, poses.at(14).Between(poses.at(12))});
    closer.AddCandidate({13, 3, poses.at(13).Between(poses.at(3))});
    closer.AddCandidate({12, 2, poses.at(12).Between(poses.at(2))});
  };
  EXPECT_EQ(VoteOnce(LoopClosingOptions{}, graph, add_return, stats).size(), 3u);
}

}  // namespace
}  // namespace longterm_mapper2d
