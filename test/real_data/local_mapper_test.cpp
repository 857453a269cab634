// Real-data tier: the local mapper (scan matching, no loop closing) against the relation ground
// truth of the Freiburg logs, compared with dead reckoning on the same data.
#include <gtest/gtest.h>

#include <ostream>

#include "real_data/real_data_support.h"

namespace longterm_mapper2d {
namespace {

using test_support::RelationErrors;
using test_support::RunCommand;
using test_support::ScopedTempDir;
using test_support::Tool;

// A log mapped with one of the shipped configurations ("" for the default).
RelationErrors MapAndEvaluate(const std::string& data, const std::string& name,
                              const std::string& config, const std::string& dir) {
  const std::string arguments =
      config.empty() ? "" : std::string(" --config ") + LTM_CONFIG_DIR + "/" + config + ".yaml";
  return test_support::MapAndEvaluate(data, name, arguments, dir + "/" + name + config + ".txt");
}

class RealDataLocalMapper : public ::testing::TestWithParam<const char*> {};

TEST_P(RealDataLocalMapper, ScanMatchingCutsTheOdometryError) {
  LTM_REQUIRE_REAL_DATA(data);
  const ScopedTempDir temp("ltm_real_data");
  const std::string& dir = temp.path();
  const RelationErrors odometry = MapAndEvaluate(data, GetParam(), "odometry_only", dir);
  const RelationErrors tracked = MapAndEvaluate(data, GetParam(), "no_loop_closing", dir);
  std::printf("%s: odometry %.3f m %.2f deg, local mapper %.3f m %.2f deg\n", GetParam(),
              odometry.mean_m, odometry.rotation_deg, tracked.mean_m, tracked.rotation_deg);
  // Without loop closing the long relations still see drift; the front end must at least cut
  // the dead-reckoning error by a quarter in translation and by half in rotation.
  EXPECT_LT(tracked.mean_m, 0.75 * odometry.mean_m);
  EXPECT_LT(tracked.rotation_deg, 0.5 * odometry.rotation_deg);
}

INSTANTIATE_TEST_SUITE_P(Freiburg, RealDataLocalMapper,
                         ::testing::Values("intel", "aces", "fr079"));

// Full SLAM, loop closing on: the back end alone (no maintenance), then the default with
// long-term maintenance. These bounds guard what the mapper reaches today (README, "Accuracy");
// the goal of beating the best published results is below them and not met yet.
struct SlamCase {
  const char* name;
  double max_translation_m;             // without maintenance
  double max_maintained_translation_m;  // the default
};

// Test names and failure messages show the log, not the struct's bytes.
void PrintTo(const SlamCase& c, std::ostream* os) { *os << c.name; }

int Nodes(const std::string& stats_json) {
  const auto pos = stats_json.find("\"graph\":");
  return pos == std::string::npos
             ? -1
             : static_cast<int>(test_support::JsonNumber(stats_json.substr(pos), "nodes"));
}

class RealDataSlam : public ::testing::TestWithParam<SlamCase> {};

TEST_P(RealDataSlam, LoopClosingRemovesTheDrift) {
  LTM_REQUIRE_REAL_DATA(data);
  const ScopedTempDir temp("ltm_real_data");
  const std::string& dir = temp.path();
  const SlamCase c = GetParam();
  const RelationErrors local = MapAndEvaluate(data, c.name, "no_loop_closing", dir);
  const RelationErrors slam = MapAndEvaluate(data, c.name, "no_maintenance", dir);
  const RelationErrors maintained = MapAndEvaluate(data, c.name, "", dir);
  std::printf(
      "%s: local mapper %.3f m %.2f deg, full SLAM %.3f m %.2f deg, with maintenance "
      "%.3f m %.2f deg\n",
      c.name, local.mean_m, local.rotation_deg, slam.mean_m, slam.rotation_deg, maintained.mean_m,
      maintained.rotation_deg);
  EXPECT_LT(slam.mean_m, c.max_translation_m);
  EXPECT_LT(slam.mean_m, 0.5 * local.mean_m);
  EXPECT_LT(slam.rotation_deg, 2.0);
  EXPECT_LT(maintained.mean_m, c.max_maintained_translation_m);
  EXPECT_LT(maintained.rotation_deg, 2.0);
}

// Long-term maintenance on one session: revisited local maps merge, so the graph is at most 0.7x
// the size it has with maintenance off.
TEST_P(RealDataSlam, MaintenanceShrinksTheGraph) {
  LTM_REQUIRE_REAL_DATA(data);
  const ScopedTempDir temp("ltm_real_data");
  const std::string& dir = temp.path();
  int nodes[2];
  for (int maintained = 0; maintained < 2; ++maintained) {
    const std::string stats = dir + "/stats" + std::to_string(maintained) + ".json";
    const auto run =
        RunCommand(Tool("offline_mapper") + test_support::LogInput(data, GetParam().name) +
                   " --stats " + stats + (maintained ? "" : " --no-maintenance"));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const auto json = RunCommand("cat " + stats);
    nodes[maintained] = Nodes(json.output);
  }
  std::printf("%s: %d nodes without maintenance, %d with\n", GetParam().name, nodes[0], nodes[1]);
  ASSERT_GT(nodes[0], 0);
  EXPECT_LT(nodes[1], 0.7 * nodes[0]);
}

INSTANTIATE_TEST_SUITE_P(Freiburg, RealDataSlam,
                         ::testing::Values(SlamCase{"intel", 0.2, 0.3},
                                           SlamCase{"aces", 0.08, 0.08},
                                           SlamCase{"fr079", 0.1, 0.1}),
                         [](const ::testing::TestParamInfo<SlamCase>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace
}  // namespace longterm_mapper2d
