// The relation metric on the Intel benchmark relations (../shared/data/intel/intel.relations).
#include <gtest/gtest.h>

#include <deque>
#include <filesystem>
#include <map>

#include "longterm_mapper2d/core/evaluation/relation_metric.h"

namespace longterm_mapper2d {
namespace {

// A trajectory over the relation stamps built by composing relations along a breadth-first
// spanning forest: every relation on the forest is reproduced exactly, the others are not.
std::vector<StampedPose2> ChainRelations(const std::vector<Relation>& relations, int* trees) {
  std::multimap<double, std::pair<double, Pose2>> edges;  // stamp -> (other stamp, this_T_other)
  for (const Relation& r : relations) {
    edges.insert({r.t1_s, {r.t2_s, r.t1_T_t2}});
    edges.insert({r.t2_s, {r.t1_s, r.t1_T_t2.inverse()}});
  }
  std::map<double, Pose2> poses;
  *trees = 0;
  for (const auto& [root, unused] : edges) {
    if (poses.count(root)) continue;
    // Each tree far from the others; relations never connect two trees.
    poses[root] = Pose2(1000.0 * ++*trees, 0.0, 0.0);
    std::deque<double> queue = {root};
    while (!queue.empty()) {
      const double stamp = queue.front();
      queue.pop_front();
      const auto range = edges.equal_range(stamp);
      for (auto it = range.first; it != range.second; ++it) {
        const auto& [other, this_T_other] = it->second;
        if (poses.count(other)) continue;
        poses[other] = poses[stamp] * this_T_other;
        queue.push_back(other);
      }
    }
  }
  std::vector<StampedPose2> trajectory;
  for (const auto& [stamp, pose] : poses) trajectory.push_back({stamp, pose});
  return trajectory;
}

TEST(RealData, IntelRelationsChainedAlongASpanningForest) {
  const std::string path = std::string(LTM_SHARED_DATA_DIR) + "/intel/intel.relations";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "skipped: no shared data at " << path;
  const auto relations = ReadRelations(path);
  ASSERT_TRUE(relations.ok()) << relations.status().message();
  int trees = 0;
  const std::vector<StampedPose2> trajectory = ChainRelations(*relations, &trees);
  ASSERT_EQ(trajectory.size(), 1791u);

  const auto result = EvaluateRelations(trajectory, *relations);
  ASSERT_TRUE(result.ok()) << result.status().message();
  EXPECT_EQ(result->matched, 2984);
  EXPECT_EQ(result->total, 2984);
  int exact = 0;
  for (const RelationError& e : result->errors) exact += e.trans_m < 1e-6 && e.rot_deg < 1e-4;
  // The forest edges (stamps minus trees) are exact; the loop-closing ones are not.
  EXPECT_EQ(exact, 1791 - trees);
  EXPECT_GT(result->trans_abs_m.mean, 0.0);
  EXPECT_LT(result->trans_abs_m.mean, 0.1);

  // Identity poses turn every error into the relation itself.
  std::vector<StampedPose2> still = trajectory;
  for (StampedPose2& p : still) p.pose = Pose2();
  const auto still_result = EvaluateRelations(still, *relations);
  ASSERT_TRUE(still_result.ok());
  const Relation& first = relations->front();
  EXPECT_NEAR(still_result->errors.front().trans_m, first.t1_T_t2.translation().norm(), 1e-12);
}

}  // namespace
}  // namespace longterm_mapper2d
