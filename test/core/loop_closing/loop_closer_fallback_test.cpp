// LoopCloser's fallback members: where a candidate set's nearest member does not align after a
// long loop, its next members are tried (LoopClosingOptions::fallback_members).
#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "longterm_mapper2d/core/loop_closing/loop_closer.h"
#include "testing/pose_graphs.h"
#include "testing/synthetic_scans.h"

namespace longterm_mapper2d {
namespace {

using test_support::CloudSeenFrom;
using test_support::OdometryGraph;

TEST(LoopCloser, AfterALongLoopTheNextMemberOfASetIsTriedWhereTheNearestFails) {
  // An old chain passes room A (node 0) and, 14 m on, room B (node 1): one candidate set. The
  // robot comes back to room A (node 2) after a long loop whose drift puts it in the graph 6 m
  // from node 1 and 8 m from node 0. The set's nearest member (1) holds another room and does not
  // align; its next member (0) does, from the heading alone.
  const auto room_a = test_support::IrregularRoom();
  auto room_b = BoxSegments(10.0, -3.0, 18.0, 3.0);
  for (const auto& box : {BoxSegments(15.5, 1.0, 16.5, 2.5), BoxSegments(11.0, -2.0, 12.0, -1.5)}) {
    room_b.insert(room_b.end(), box.begin(), box.end());
  }
  auto world = room_a;
  world.insert(world.end(), room_b.begin(), room_b.end());
  const Pose2 old_a(0.0, 0.0, 0.0), old_b(14.0, 0.0, 0.0), new_truth(0.3, 0.2, 0.1);
  PoseGraph graph =
      OdometryGraph({{0, old_a}, {1, old_b}, {3, Pose2(0.0, 20.0, 0.0)}, {2, Pose2(8.0, 0.5, 0.1)}},
                    {{0, 1}, {1, 3}, {3, 2}}, Eigen::Vector3d(0.2, 0.2, 100.0));
  graph.mutable_node(1).stamp_s = 100.0;
  graph.mutable_node(3).stamp_s = 500.0;
  graph.mutable_node(2).stamp_s = 1000.0;
  const std::map<GraphNodeId, Cloud> clouds = {{0, CloudSeenFrom(world, old_a, 8)},
                                               {1, CloudSeenFrom(world, old_b, 8)},
                                               {2, CloudSeenFrom(world, new_truth, 8)}};
  auto cloud_of = [&](GraphNodeId id) -> const Cloud& { return clouds.at(id); };
  auto search = [&](const LoopClosingOptions& options, MapperStats* stats) {
    LoopCloser closer(options, RegistrationOptions{});
    closer.SearchFrom(graph, 2, cloud_of, *stats, false);
    return closer.buffer();
  };
  MapperStats stats;
  const std::vector<ClosureCandidate> found = search(LoopClosingOptions{}, &stats);
  EXPECT_EQ(stats.counters["loop_closure_alignments"], 2u);
  EXPECT_EQ(stats.counters["loop_closure_alignments_fallback"], 1u);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found.front().old, 0);
  const Pose2 truth = new_truth.Between(old_a);
  EXPECT_LT((found.front().local_T_old.translation() - truth.translation()).norm(), 0.02);
  EXPECT_LT(std::abs(NormalizeAngle(found.front().local_T_old.theta() - truth.theta())), 0.01);
  // The nearest alone, or a next member made too recently to have drifted: nothing.
  LoopClosingOptions nearest_only;
  nearest_only.fallback_members = 0;
  MapperStats plain_stats;
  EXPECT_TRUE(search(nearest_only, &plain_stats).empty());
  EXPECT_EQ(plain_stats.counters["loop_closure_alignments"], 1u);
  LoopClosingOptions young;
  young.fallback_min_age_s = 1500.0;
  EXPECT_TRUE(search(young, &plain_stats).empty());
}

}  // namespace
}  // namespace longterm_mapper2d
