// Real-data tier: the local mapper (scan matching, no loop closing) against the relation ground
// truth of the Freiburg logs, compared with dead reckoning on the same data.
#include <gtest/gtest.h>

#include <ostream>

#include "real_data/real_data_support.h"

namespace longterm_mapper2d {
namespace {

using test_support::JsonNumber;
using test_support::RunCommand;
using test_support::TempDir;
using test_support::Tool;

struct Errors {
  double translation_m;
  double rotation_deg;
};

Errors MapAndEvaluate(const std::string& data, const std::string& name, const std::string& config,
                      const std::string& dir) {
  const std::string trajectory = dir + "/" + name + config + ".txt";
  std::string args = test_support::LogInput(data, name) + " --trajectory " + trajectory;
  if (!config.empty()) args += std::string(" --config ") + LTM_CONFIG_DIR + "/" + config + ".yaml";
  const auto run = RunCommand(Tool("offline_mapper") + args);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  const auto eval = RunCommand(Tool("evaluate_relations") + " --json --trajectory " + trajectory +
                               " --relations " + data + "/" + name + "/" + name + ".relations");
  EXPECT_EQ(eval.exit_code, 0) << eval.output;
  return {JsonNumber(eval.output, "trans_abs_mean_m"), JsonNumber(eval.output, "rot_abs_mean_deg")};
}

class RealDataLocalMapper : public ::testing::TestWithParam<const char*> {};

TEST_P(RealDataLocalMapper, ScanMatchingCutsTheOdometryError) {
  LTM_REQUIRE_REAL_DATA(data);
  const std::string dir = TempDir();
  const Errors odometry = MapAndEvaluate(data, GetParam(), "odometry_only", dir);
  const Errors tracked = MapAndEvaluate(data, GetParam(), "no_loop_closing", dir);
  std::printf("%s: odometry %.3f m %.2f deg, local mapper %.3f m %.2f deg\n", GetParam(),
              odometry.translation_m, odometry.rotation_deg, tracked.translation_m,
              tracked.rotation_deg);
  // Without loop closing the long relations still see drift; the front end must at least cut
  // the dead-reckoning error by a quarter in translation and by half in rotation.
  EXPECT_LT(tracked.translation_m, 0.75 * odometry.translation_m);
  EXPECT_LT(tracked.rotation_deg, 0.5 * odometry.rotation_deg);
}

INSTANTIATE_TEST_SUITE_P(Freiburg, RealDataLocalMapper,
                         ::testing::Values("intel", "aces", "fr079"));

// Full SLAM, loop closing on: the back end alone (no maintenance), then the default with
// long-term maintenance. These bounds guard what the mapper reaches today (README, "Accuracy");
// the goal of beating the best published results is below them and not met yet.
struct SlamCase {
  const char* name;
  double max_translation_m;              // without maintenance
  double max_maintained_translation_m;   // the default
};

// Test names and failure messages show the log, not the struct's bytes.
void PrintTo(const SlamCase& c, std::ostream* os) { *os << c.name; }

int Nodes(const std::string& stats_json) {
  const auto pos = stats_json.find("\"graph\":");
  return pos == std::string::npos ? -1
                                  : static_cast<int>(test_support::JsonNumber(
                                        stats_json.substr(pos), "nodes"));
}

class RealDataSlam : public ::testing::TestWithParam<SlamCase> {};

TEST_P(RealDataSlam, LoopClosingRemovesTheDrift) {
  LTM_REQUIRE_REAL_DATA(data);
  const std::string dir = TempDir();
  const SlamCase c = GetParam();
  const Errors local = MapAndEvaluate(data, c.name, "no_loop_closing", dir);
  const Errors slam = MapAndEvaluate(data, c.name, "no_maintenance", dir);
  const Errors maintained = MapAndEvaluate(data, c.name, "", dir);
  std::printf("%s: local mapper %.3f m %.2f deg, full SLAM %.3f m %.2f deg, with maintenance "
              "%.3f m %.2f deg\n", c.name, local.translation_m, local.rotation_deg,
              slam.translation_m, slam.rotation_deg, maintained.translation_m,
              maintained.rotation_deg);
  EXPECT_LT(slam.translation_m, c.max_translation_m);
  EXPECT_LT(slam.translation_m, 0.5 * local.translation_m);
  EXPECT_LT(slam.rotation_deg, 2.0);
  EXPECT_LT(maintained.translation_m, c.max_maintained_translation_m);
  EXPECT_LT(maintained.rotation_deg, 2.0);
}

// Long-term maintenance on one session: revisited local maps merge, so the graph is at most 0.7x
// the size it has with maintenance off.
TEST_P(RealDataSlam, MaintenanceShrinksTheGraph) {
  LTM_REQUIRE_REAL_DATA(data);
  const std::string dir = TempDir();
  int nodes[2];
  for (int maintained = 0; maintained < 2; ++maintained) {
    const std::string stats = dir + "/stats" + std::to_string(maintained) + ".json";
    const auto run = RunCommand(Tool("offline_mapper") + test_support::LogInput(data, GetParam().name) +
                                " --stats " + stats +
                                (maintained ? "" : " --no-maintenance"));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const auto json = RunCommand("cat " + stats);
    nodes[maintained] = Nodes(json.output);
  }
  std::printf("%s: %d nodes without maintenance, %d with\n", GetParam().name, nodes[0], nodes[1]);
  ASSERT_GT(nodes[0], 0);
  EXPECT_LT(nodes[1], 0.7 * nodes[0]);
}

INSTANTIATE_TEST_SUITE_P(Freiburg, RealDataSlam,
                         ::testing::Values(SlamCase{"intel", 0.2, 0.3}, SlamCase{"aces", 0.08, 0.08},
                                           SlamCase{"fr079", 0.1, 0.1}),
                         [](const ::testing::TestParamInfo<SlamCase>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace
}  // namespace longterm_mapper2d
