#include "longterm_mapper2d/core/loop_closing/loop_closer.h"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "testing/pose_graphs.h"
#include "testing/synthetic_scans.h"

namespace longterm_mapper2d {
namespace {

using test_support::CloudSeenFrom;
using test_support::OdometryGraph;

// What Validate says of `options` ("" when they are valid).
std::string ErrorsOf(const LoopClosingOptions& options) {
  OptionErrors errors;
  options.Validate(errors);
  return errors.ToString();
}

TEST(LoopCloser, AlignsTwoLocalMapsOfOnePlaceFromADriftedGuess) {
  const auto room = test_support::IrregularRoom();
  const Pose2 a(0.0, 0.0, 0.0), b(1.2, 0.6, 0.5);
  LoopCloser closer(LoopClosingOptions{}, RegistrationOptions{});
  const Pose2 truth = a.Between(b);
  const Pose2 drifted = truth * Pose2(0.4, -0.3, 0.12);
  const auto aligned =
      closer.AlignLocalMaps(CloudSeenFrom(room, a, 20), CloudSeenFrom(room, b, 20), {drifted});
  ASSERT_TRUE(aligned.has_value());
  EXPECT_LT((aligned->translation() - truth.translation()).norm(), 0.02);
  EXPECT_LT(std::abs(NormalizeAngle(aligned->theta() - truth.theta())), 0.01);
}

TEST(LoopCloser, ASymmetricCorridorGivesNoClosure) {
  // Two places 4 m apart in a featureless corridor look the same: the alignment is degenerate
  // along the corridor and must be refused, not turned into a false closure.
  const auto corridor = test_support::Corridor();
  LoopCloser closer(LoopClosingOptions{}, RegistrationOptions{});
  const auto aligned =
      closer.AlignLocalMaps(CloudSeenFrom(corridor, Pose2(0, 0, 0), 8.0),
                            CloudSeenFrom(corridor, Pose2(4, 0, 0), 8.0), {Pose2()});
  EXPECT_FALSE(aligned.has_value());
}

// The room as the new node sees it: cabinets now stand 1.2 m in front of three of its walls, so
// from the new node most of what an old map of the room holds lies hidden behind them.
std::vector<Segment> RoomWithCabinets() {
  auto room = test_support::IrregularRoom();
  room.push_back({Eigen::Vector2d(-3.8, -1.8), Eigen::Vector2d(3.5, -1.8)});
  room.push_back({Eigen::Vector2d(3.8, -0.5), Eigen::Vector2d(3.8, 2.8)});
  room.push_back({Eigen::Vector2d(-3.8, -0.8), Eigen::Vector2d(-3.8, 2.8)});
  return room;
}

TEST(LoopCloser, AnOldMapHiddenInPartBehindTheNewOneStillAligns) {
  const Pose2 a(-1.0, 0.5, 0.0), b(1.2, 0.6, 0.5);
  const Pose2 truth = a.Between(b);
  const Cloud old_map = CloudSeenFrom(test_support::IrregularRoom(), a, 20);
  const Cloud new_map = CloudSeenFrom(RoomWithCabinets(), b, 20);
  const Pose2 guess = truth * Pose2(0.3, -0.2, 0.08);
  LoopClosingOptions options;
  options.partial_overlap = true;
  LoopCloser closer(options, RegistrationOptions{});
  const auto aligned = closer.AlignLocalMaps(new_map, old_map, {guess.inverse()});
  ASSERT_TRUE(aligned.has_value());
  EXPECT_LT((aligned->translation() - truth.inverse().translation()).norm(), 0.02);
  EXPECT_LT(std::abs(NormalizeAngle(aligned->theta() + truth.theta())), 0.01);
  // Counted as disagreement (the default), the hidden walls refuse the same alignment.
  options.partial_overlap = false;
  LoopCloser strict(options, RegistrationOptions{});
  EXPECT_FALSE(strict.AlignLocalMaps(new_map, old_map, {guess.inverse()}).has_value());
}

TEST(LoopCloser, AnOldSurfaceWhereTheNewMapSeesThroughRefusesAPartialOverlap) {
  // As above, but the old map also holds crates in what the new node sees as free space: old
  // surfaces in front of the new map's are evidence against the alignment.
  const Pose2 a(-1.0, 0.5, 0.0), b(1.2, 0.6, 0.5);
  const Pose2 truth = a.Between(b);
  auto old_room = test_support::IrregularRoom();
  for (const auto& box : {BoxSegments(-0.2, 2.2, 0.6, 2.8), BoxSegments(2.6, 2.4, 3.2, 3.0),
                          BoxSegments(-2.6, 1.8, -1.8, 2.6)}) {
    old_room.insert(old_room.end(), box.begin(), box.end());
  }
  const Cloud old_map = CloudSeenFrom(old_room, a, 20);
  const Cloud new_map = CloudSeenFrom(RoomWithCabinets(), b, 20);
  LoopClosingOptions options;
  options.partial_overlap = true;
  LoopCloser closer(options, RegistrationOptions{});
  EXPECT_FALSE(closer.AlignLocalMaps(new_map, old_map, {truth.inverse()}).has_value());
  // Without the crates the same alignment validates.
  EXPECT_TRUE(closer
                  .AlignLocalMaps(new_map, CloudSeenFrom(test_support::IrregularRoom(), a, 20),
                                  {truth.inverse()})
                  .has_value());
}

TEST(LoopCloser, ALoadedMapsNodeAtTheStartIsACandidateOfTheSessionsFirstNode) {
  // A session on a loaded map: its first node (session 1) is tied to the loaded node where it
  // starts (session 0) by the odometry edge of the initial pose, and the next node of its own
  // session follows 1.5 m on. The loaded node is searched (the tie is no tracker measurement);
  // the session's own neighbour, nearer than min_graph_distance_m along odometry, is not.
  const auto room = test_support::IrregularRoom();
  const Pose2 start(-1.0, 0.0, 0.0), next(0.5, 0.2, 0.1);
  PoseGraph graph;
  for (const auto& [id, session, pose] :
       {std::tuple<GraphNodeId, int, Pose2>{0, 0, start}, {1, 1, start}, {2, 1, next}}) {
    GraphNode node;
    node.id = id;
    node.session_id = session;
    node.pose = pose;
    ASSERT_TRUE(graph.AddNode(node).ok());
  }
  for (const auto& [from, to] : {std::pair<GraphNodeId, GraphNodeId>{0, 1}, {1, 2}}) {
    GraphEdge edge;
    edge.from = from;
    edge.to = to;
    edge.measurement = graph.node(from).pose.Between(graph.node(to).pose);
    edge.information = Eigen::Vector3d(4.0, 4.0, 25.0).asDiagonal();
    edge.kind = EdgeKind::kOdometry;
    ASSERT_TRUE(graph.AddEdge(edge).ok());
  }
  const std::map<GraphNodeId, Cloud> clouds = {{0, CloudSeenFrom(room, start, 8)},
                                               {1, CloudSeenFrom(room, start, 8)},
                                               {2, CloudSeenFrom(room, next, 8)}};
  auto cloud_of = [&](GraphNodeId id) -> const Cloud& { return clouds.at(id); };
  MapperStats stats;
  LoopCloser closer(LoopClosingOptions{}, RegistrationOptions{});
  closer.SearchFrom(graph, 1, cloud_of, stats, false);
  EXPECT_EQ(stats.counters["loop_closure_alignments"], 1u);
  ASSERT_EQ(closer.buffer().size(), 1u);
  EXPECT_EQ(closer.buffer().front().old, 0);
  EXPECT_LT(closer.buffer().front().local_T_old.translation().norm(), 0.02);
}

TEST(LoopCloser, AfterATrackerFailureATurnedNodeIsStillAligned) {
  // The new node, 6 m from the old one, has a heading 0.75 rad off in the graph (a wrong
  // registration while turning in place): aligning from the graph's guess fails; in doubt, the
  // turned guesses find the truth.
  const auto room = test_support::IrregularRoom();
  const Pose2 old_pose(-3.0, -1.0, 0.0), new_truth(2.5, 1.5, 0.3);
  PoseGraph graph;
  GraphNode old_node, new_node;
  old_node.id = 0;
  old_node.pose = old_pose;
  new_node.id = 1;
  new_node.pose = new_truth * Pose2(0.0, 0.0, 0.75);
  ASSERT_TRUE(graph.AddNode(old_node).ok());
  ASSERT_TRUE(graph.AddNode(new_node).ok());
  GraphEdge weak;  // a merge's condensed edge: no odometry path, so node 0 is a candidate
  weak.from = 0;
  weak.to = 1;
  weak.measurement = old_node.pose.Between(new_node.pose);
  weak.information = 0.01 * Eigen::Matrix3d::Identity();
  weak.kind = EdgeKind::kCondensed;
  ASSERT_TRUE(graph.AddEdge(weak).ok());
  const std::map<GraphNodeId, Cloud> clouds = {{0, CloudSeenFrom(room, old_pose, 8)},
                                               {1, CloudSeenFrom(room, new_truth, 8)}};
  auto cloud_of = [&](GraphNodeId id) -> const Cloud& { return clouds.at(id); };
  MapperStats stats;
  LoopCloser confident(LoopClosingOptions{}, RegistrationOptions{});
  confident.SearchFrom(graph, 1, cloud_of, stats, false);
  EXPECT_TRUE(confident.buffer().empty());
  EXPECT_EQ(stats.counters["loop_closure_alignments"], 1u);
  LoopCloser in_doubt(LoopClosingOptions{}, RegistrationOptions{});
  in_doubt.SearchFrom(graph, 1, cloud_of, stats, true);
  ASSERT_EQ(in_doubt.buffer().size(), 1u);
  const Pose2 truth = new_truth.Between(old_pose);
  const Pose2& found = in_doubt.buffer().front().local_T_old;
  EXPECT_LT((found.translation() - truth.translation()).norm(), 0.02);
  EXPECT_LT(std::abs(NormalizeAngle(found.theta() - truth.theta())), 0.01);
  EXPECT_EQ(stats.counters["loop_closure_alignments_turned"], 1u);
  // Switched off, doubt changes nothing.
  LoopClosingOptions off;
  off.recovery_heading_steps = 0;
  LoopCloser plain(off, RegistrationOptions{});
  plain.SearchFrom(graph, 1, cloud_of, stats, true);
  EXPECT_TRUE(plain.buffer().empty());
}

TEST(LoopCloser, ARevisitBeyondTheAlignmentsBasinIsFoundByTheCorrelativeSearch) {
  // The graph has the new node 2.2 m and 0.15 rad from where its cloud was taken (drift along a
  // long chain, loose enough for the candidate gate): the alignment fails from the graph's guess
  // and from the heading alone; the correlative search over the marginal's window finds the
  // place, and the alignment from there the truth.
  const auto room = test_support::IrregularRoom();
  const Pose2 old_pose(-3.0, -1.0, 0.0), new_truth(2.5, 1.5, 0.3);
  const Pose2 new_in_graph = Pose2(1.8, -1.2, 0.0) * new_truth * Pose2(0.0, 0.0, 0.15);
  const PoseGraph graph =
      OdometryGraph({{0, old_pose}, {1, new_in_graph}, {2, Pose2(0.0, 20.0, 0.0)}},
                    {{0, 2}, {2, 1}}, Eigen::Vector3d(0.2, 0.2, 100.0));
  const std::map<GraphNodeId, Cloud> clouds = {{0, CloudSeenFrom(room, old_pose, 8)},
                                               {1, CloudSeenFrom(room, new_truth, 8)}};
  auto cloud_of = [&](GraphNodeId id) -> const Cloud& { return clouds.at(id); };
  MapperStats stats;
  LoopCloser plain(LoopClosingOptions{}, RegistrationOptions{});  // off by default
  plain.SearchFrom(graph, 1, cloud_of, stats, false);
  EXPECT_TRUE(plain.buffer().empty());
  ASSERT_EQ(stats.counters["loop_closure_alignments"], 1u);  // it was a candidate
  LoopClosingOptions on;
  on.correlative_search = true;
  LoopCloser searching(on, RegistrationOptions{});
  searching.SearchFrom(graph, 1, cloud_of, stats, false);
  ASSERT_EQ(searching.buffer().size(), 1u);
  const Pose2 truth = new_truth.Between(old_pose);
  const Pose2& found = searching.buffer().front().local_T_old;
  EXPECT_LT((found.translation() - truth.translation()).norm(), 0.02);
  EXPECT_LT(std::abs(NormalizeAngle(found.theta() - truth.theta())), 0.01);
  EXPECT_EQ(stats.counters["loop_closure_correlative_searches"], 1u);
  EXPECT_EQ(stats.counters["loop_closure_alignments_correlative"], 1u);
  // A window narrower than the offset does not reach it.
  LoopClosingOptions narrow = on;
  narrow.correlative_max_window_m = 1.0;
  LoopCloser short_reach(narrow, RegistrationOptions{});
  short_reach.SearchFrom(graph, 1, cloud_of, stats, false);
  EXPECT_TRUE(short_reach.buffer().empty());
}

TEST(LoopCloser, FallbackOptionsAreValidated) {
  LoopClosingOptions options;
  options.fallback_members = -1;
  EXPECT_NE(ErrorsOf(options).find("fallback_members"), std::string::npos);
  options = LoopClosingOptions{};
  options.fallback_min_spacing_m = -0.5;
  EXPECT_NE(ErrorsOf(options).find("fallback_min_spacing_m"), std::string::npos);
  options = LoopClosingOptions{};
  options.fallback_min_age_s = -1.0;
  EXPECT_NE(ErrorsOf(options).find("fallback_min_age_s"), std::string::npos);
}

TEST(LoopCloser, CorrelativeSearchOptionsAreValidated) {
  EXPECT_EQ(ErrorsOf(LoopClosingOptions{}), "");
  LoopClosingOptions options;
  options.correlative_max_window_m = 0.0;
  EXPECT_NE(ErrorsOf(options).find("correlative_max_window_m"), std::string::npos);
  options = LoopClosingOptions{};
  options.correlative_min_window_m = 6.0;  // above the maximum, 5
  EXPECT_NE(ErrorsOf(options).find("correlative_max_window_m"), std::string::npos);
  options = LoopClosingOptions{};
  options.correlative_min_window_rad = 0.6;  // above the maximum, 0.5
  EXPECT_NE(ErrorsOf(options).find("correlative_max_window_rad"), std::string::npos);
  options = LoopClosingOptions{};
  options.correlative_min_score = 1.5;
  EXPECT_NE(ErrorsOf(options).find("correlative_min_score"), std::string::npos);
  options = LoopClosingOptions{};
  options.correlative_resolution_m = 0.0;
  EXPECT_NE(ErrorsOf(options).find("correlative_resolution_m"), std::string::npos);
  options = LoopClosingOptions{};
  options.correlative_window_sigmas = -1.0;
  EXPECT_NE(ErrorsOf(options).find("correlative_window_sigmas"), std::string::npos);
}

TEST(LoopCloser, WeakAlignmentOptionsAreValidated) {
  LoopClosingOptions options;
  EXPECT_EQ(ErrorsOf(options), "");
  options.weak_information_ratio = options.min_information_ratio / 2;
  EXPECT_NE(ErrorsOf(options).find("weak_information_ratio"), std::string::npos);
  options = LoopClosingOptions{};
  options.weak_min_inlier_ratio = 1.5;
  EXPECT_NE(ErrorsOf(options).find("weak_min_inlier_ratio"), std::string::npos);
}

TEST(LoopCloser, PartialOverlapOptionsAreValidated) {
  LoopClosingOptions options;
  options.partial_min_inlier_ratio = 0.6;  // above min_inlier_ratio, 0.5
  EXPECT_NE(ErrorsOf(options).find("partial_min_inlier_ratio"), std::string::npos);
  options = LoopClosingOptions{};
  options.partial_min_inlier_ratio = 0.0;
  EXPECT_NE(ErrorsOf(options).find("partial_min_inlier_ratio"), std::string::npos);
  options = LoopClosingOptions{};
  options.partial_min_agreement = 1.2;
  EXPECT_NE(ErrorsOf(options).find("partial_min_agreement"), std::string::npos);
}

TEST(LoopCloser, AnAlignmentFarOutsideTheGraphsUncertaintyIsNotKept) {
  // The clouds of nodes 0 and 1 are of one place (1 is 0.5 m from 0), but the graph, through
  // node 2 (0.8 m between 0 and 1: loose enough for the candidate gate), has node 1 2.5 m
  // farther: from its guess the alignment does not validate, from the heading alone it does,
  // 2.5 m (3 sigma) from where the graph has it. Along a corridor this is how an alignment that
  // slid to a look-alike stretch gets in.
  const auto room = test_support::IrregularRoom();
  const Pose2 old_pose(0.0, 0.0, 0.0), new_in_clouds(0.5, 0.3, 0.1);
  const Pose2 new_in_graph = Pose2(2.5, 0.0, 0.0) * new_in_clouds;
  const PoseGraph graph =
      OdometryGraph({{0, old_pose}, {1, new_in_graph}, {2, Pose2(1.0, 12.0, 0.0)}},
                    {{0, 2}, {2, 1}}, Eigen::Vector3d(3.0, 3.0, 1e4));
  const std::map<GraphNodeId, Cloud> clouds = {{0, CloudSeenFrom(room, old_pose, 8)},
                                               {1, CloudSeenFrom(room, new_in_clouds, 8)}};
  auto cloud_of = [&](GraphNodeId id) -> const Cloud& { return clouds.at(id); };
  LoopClosingOptions options;
  options.innovation_gate = 0.0;
  MapperStats stats;
  LoopCloser ungated(options, RegistrationOptions{});
  ungated.SearchFrom(graph, 1, cloud_of, stats, false);
  ASSERT_EQ(ungated.buffer().size(), 1u);
  const Pose2 in_clouds = new_in_clouds.Between(old_pose);
  EXPECT_LT((ungated.buffer().front().local_T_old.translation() - in_clouds.translation()).norm(),
            0.02);
  LoopCloser gated(LoopClosingOptions{}, RegistrationOptions{});
  gated.SearchFrom(graph, 1, cloud_of, stats, false);
  EXPECT_TRUE(gated.buffer().empty());
  EXPECT_EQ(stats.counters["loop_closure_alignments_implausible"], 1u);
}

TEST(LoopCloser, AnAlignmentFarFromAShortTrackerChainIsNotKept) {
  // As above, but the tracker's chain from node 0 to node 1 (through node 2) is 7.6 m long and
  // loose enough for both gates; the alignment puts node 1 4 m from where that chain has it,
  // beyond what the tracker drifts over it (0.5 m + 0.3 * 7.6 m). Aces' corridors gave such
  // closures 6-7 m long between nodes two or three apart.
  const auto room = test_support::IrregularRoom();
  const Pose2 old_pose(0.0, 0.0, 0.0), new_in_clouds(0.5, 0.3, 0.1);
  const Pose2 new_in_graph = Pose2(4.0, 0.0, 0.0) * new_in_clouds;
  const PoseGraph graph =
      OdometryGraph({{0, old_pose}, {1, new_in_graph}, {2, Pose2(1.0, 3.0, 0.0)}}, {{0, 2}, {2, 1}},
                    Eigen::Vector3d(0.5, 0.5, 1e4));
  const std::map<GraphNodeId, Cloud> clouds = {{0, CloudSeenFrom(room, old_pose, 8)},
                                               {1, CloudSeenFrom(room, new_in_clouds, 8)}};
  auto cloud_of = [&](GraphNodeId id) -> const Cloud& { return clouds.at(id); };
  LoopClosingOptions options;
  options.innovation_gate = 0.0;
  options.chain_gate_max_path_m = 0.0;
  MapperStats stats;
  LoopCloser unchained(options, RegistrationOptions{});
  unchained.SearchFrom(graph, 1, cloud_of, stats, false);
  ASSERT_EQ(unchained.buffer().size(), 1u);  // the clouds do align
  options.chain_gate_max_path_m = 30.0;
  LoopCloser chained(options, RegistrationOptions{});
  chained.SearchFrom(graph, 1, cloud_of, stats, false);
  EXPECT_TRUE(chained.buffer().empty());
  EXPECT_EQ(stats.counters["loop_closure_alignments_against_chain"], 1u);
  // A longer allowance per metre lets it through.
  options.chain_gate_per_m = 0.5;
  LoopCloser lenient(options, RegistrationOptions{});
  lenient.SearchFrom(graph, 1, cloud_of, stats, false);
  EXPECT_EQ(lenient.buffer().size(), 1u);
}

TEST(LoopCloser, AWaitingLoopIsTriedFromTheNextNodeWhereItPutsIt) {
  // Nodes 10 and 11 revisit old nodes 0 and 1, but the graph has drifted 30 m away: no old node
  // is near enough to search. Node 10's closure with node 0 waits for support; it says where node
  // 11 is against node 0 and its neighbour 1, and there node 11 is aligned with both.
  const auto room = test_support::IrregularRoom();
  const std::map<GraphNodeId, Pose2> truth = {{0, Pose2(0.0, 0.0, 0.0)},
                                              {1, Pose2(1.0, 0.5, 0.2)},
                                              {10, Pose2(0.5, 0.3, 0.1)},
                                              {11, Pose2(0.8, -0.4, -0.2)}};
  const Pose2 drift(30.0, 0.0, 0.5);
  std::map<GraphNodeId, Pose2> in_graph;
  std::map<GraphNodeId, Cloud> clouds;
  for (const auto& [id, pose] : truth) {
    in_graph[id] = id >= 10 ? drift * pose : pose;
    clouds[id] = CloudSeenFrom(room, pose, 8);
  }
  const PoseGraph graph =
      OdometryGraph(in_graph, {{0, 1}, {10, 11}}, Eigen::Vector3d(100.0, 100.0, 1e3));
  auto cloud_of = [&](GraphNodeId id) -> const Cloud& { return clouds.at(id); };
  for (const bool predict : {false, true}) {
    LoopClosingOptions options;
    options.vote_predict_from_waiting = predict;
    LoopCloser closer(options, RegistrationOptions{});
    closer.AddCandidate({10, 0, truth.at(10).Between(truth.at(0))});
    MapperStats stats;
    closer.SearchFrom(graph, 11, cloud_of, stats, false);
    if (!predict) {
      EXPECT_EQ(closer.buffer().size(), 1u);
      EXPECT_EQ(stats.counters["loop_closure_alignments"], 0u);
      continue;
    }
    ASSERT_EQ(closer.buffer().size(), 3u);
    EXPECT_EQ(stats.counters["loop_closure_alignments"], 2u);
    for (std::size_t i = 1; i < 3; ++i) {
      const ClosureCandidate& found = closer.buffer()[i];
      EXPECT_EQ(found.local, 11);
      const Pose2 expected = truth.at(11).Between(truth.at(found.old));
      EXPECT_LT((found.local_T_old.translation() - expected.translation()).norm(), 0.02);
      EXPECT_LT(std::abs(NormalizeAngle(found.local_T_old.theta() - expected.theta())), 0.01);
    }
  }
}

}  // namespace
}  // namespace longterm_mapper2d
