// Real-data tier: full SLAM (the default configuration) against the published results on the
// Freiburg logs (Hess et al., ICRA 2016, Table I), where the mapper reaches them today.
#include <gtest/gtest.h>

#include <string>

#include "real_data/real_data_support.h"

namespace longterm_mapper2d {
namespace {

using test_support::MapAndEvaluate;
using test_support::RelationErrors;
using test_support::ScopedTempDir;

// The bag's base_link -> laser transform puts the laser 0.04 m ahead of the base; the original
// log's parameter (robot_frontlaser_offset -0.04, in the GMapping-corrected copy of that log)
// puts it 0.04 m behind, and the relations agree with the original: mapped with that mount the
// log beats the published 0.0452 m (README, "Accuracy": 0.032 m, five robustness runs
// 0.032-0.033 m; with the bag's mount 0.068 m).
// The bag only: its CARMEN copy (the ROS-free build's input), the same scans with the odometry of
// each laser line, has a tracker failure at 2212 s with this mount and ends 3 m off (0.157 m;
// README, "Accuracy": not solved).
TEST(RealDataBenchmark, Fr079WithTheOriginalLaserMountBeatsThePublishedResult) {
  LTM_REQUIRE_REAL_DATA(data);
#ifndef LTM_READS_BAGS
  GTEST_SKIP() << "needs fr079.bag (a build with the ROS layer): the CARMEN copy fails it";
#endif
  const ScopedTempDir temp("ltm_real_data");
  const RelationErrors r =
      MapAndEvaluate(data, "fr079", " --laser-mount -0.04,0,0", temp.path() + "/fr079.txt");
  std::printf("fr079, laser mount -0.04 m: %.4f m (max %.3f m), %.3f deg\n", r.mean_m, r.max_m,
              r.rotation_deg);
  EXPECT_LT(r.mean_m, 0.0452);
  EXPECT_LT(r.max_m, 0.5);
  EXPECT_LT(r.rotation_deg, 1.0);
}

// Aces' return to its start, missed while the graph was 9 m off there, is closed by the final
// sweep: no relation error above 0.5 m (0.84 m without the sweep; 0.42 m with it) and the mean
// within 0.04 m (0.043 without, 0.037 with; the published result is 0.0375).
TEST(RealDataBenchmark, AcesReturnToItsStartIsClosed) {
  LTM_REQUIRE_REAL_DATA(data);
  const ScopedTempDir temp("ltm_real_data");
  const RelationErrors r = MapAndEvaluate(data, "aces", "", temp.path() + "/aces.txt");
  std::printf("aces: %.4f m (max %.3f m), %.3f deg\n", r.mean_m, r.max_m, r.rotation_deg);
  EXPECT_LT(r.mean_m, 0.040);
  EXPECT_LT(r.max_m, 0.5);
  EXPECT_LT(r.rotation_deg, 1.0);
}

}  // namespace
}  // namespace longterm_mapper2d
