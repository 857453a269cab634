// Real-data tier: data in, evaluation out, on the intel log (odometry and the relation metric).
#include <gtest/gtest.h>

#include <cmath>

#include "longterm_mapper2d/core/io/trajectory_io.h"
#include "real_data/real_data_support.h"

namespace longterm_mapper2d {
namespace {

using test_support::JsonNumber;
using test_support::RunCommand;
using test_support::ScopedTempDir;
using test_support::Tool;

#ifdef LTM_READS_BAGS
// Both readers of the same log agree; the ROS-free build reads no bags and runs the real-data
// tier on the CARMEN copies, which this test vouches for.
TEST(RealDataIntel, BagAndCarmenLogGiveTheSameOdometryTrajectory) {
  LTM_REQUIRE_REAL_DATA(data);
  const ScopedTempDir temp("ltm_real_data");
  const std::string& dir = temp.path();
  // Odometry only: registration and loop closing are switched off through the config.
  const std::string config = std::string(" --config ") + LTM_CONFIG_DIR + "/odometry_only.yaml";
  const auto bag = RunCommand(Tool("offline_mapper") + " --bag " + data + "/intel/intel.bag" +
                              config + " --trajectory " + dir + "/bag.txt");
  ASSERT_EQ(bag.exit_code, 0) << bag.output;
  const auto log = RunCommand(Tool("offline_mapper") + " --carmen " + data +
                              "/intel/intel.reconstructed.clf" + config + " --trajectory " + dir +
                              "/clf.txt");
  ASSERT_EQ(log.exit_code, 0) << log.output;
  const auto from_bag = ReadTrajectory(dir + "/bag.txt");
  const auto from_log = ReadTrajectory(dir + "/clf.txt");
  ASSERT_TRUE(from_bag.ok() && from_log.ok());
  ASSERT_EQ(from_bag->size(), 13631u);
  ASSERT_EQ(from_log->size(), 13631u);
  double max_position_diff = 0.0, max_stamp_diff = 0.0;
  for (std::size_t i = 0; i < from_bag->size(); ++i) {
    const auto& a = (*from_bag)[i];
    const auto& b = (*from_log)[i];
    max_stamp_diff = std::max(max_stamp_diff, std::abs(a.stamp_s - b.stamp_s));
    max_position_diff =
        std::max(max_position_diff, (a.pose.translation() - b.pose.translation()).norm());
  }
  EXPECT_LT(max_stamp_diff, 1e-5);
  EXPECT_LT(max_position_diff, 1e-5);
}
#endif  // LTM_READS_BAGS

TEST(RealDataIntel, EvaluateRelationsMatchesEveryIntelRelation) {
  LTM_REQUIRE_REAL_DATA(data);
  const ScopedTempDir temp("ltm_real_data");
  const std::string& dir = temp.path();
  const auto run = RunCommand(Tool("offline_mapper") + test_support::LogInput(data, "intel") +
                              " --config " + LTM_CONFIG_DIR +
                              "/odometry_only.yaml --trajectory " + dir + "/odom.txt");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto eval = RunCommand(Tool("evaluate_relations") + " --json --trajectory " + dir +
                               "/odom.txt --relations " + data + "/intel/intel.relations");
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_EQ(JsonNumber(eval.output, "matched"), 2984) << eval.output;
  EXPECT_EQ(JsonNumber(eval.output, "total"), 2984) << eval.output;
  // Raw odometry drifts by metres on intel: the baseline every later stage improves on.
  EXPECT_GT(JsonNumber(eval.output, "trans_abs_mean_m"), 1.0) << eval.output;
}

}  // namespace
}  // namespace longterm_mapper2d
