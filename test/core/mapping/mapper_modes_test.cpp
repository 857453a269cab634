#include <gtest/gtest.h>

#include <algorithm>
#include <optional>

#include "longterm_mapper2d/core/map/session_map_file.h"
#include "longterm_mapper2d/core/mapping/mapper.h"
#include "longterm_mapper2d/core/simulation/session_simulator.h"
#include "testing/simulated_mapping.h"
#include "testing/small_room_sessions.h"

namespace longterm_mapper2d {
namespace {

using test_support::MapSession;
using test_support::SessionResult;
using test_support::SmallRoomSession;

// Localization on a saved map: the robot is tracked in the map's frame (even from a wrong
// initial pose), and the map is not changed.
TEST(MultiSession, LocalizationTracksOnAFrozenMap) {
  const auto world = LoadWorld(std::string(LTM_CONFIG_DIR) + "/worlds/small_room.yaml");
  ASSERT_TRUE(world.ok());
  const SessionResult first = MapSession(*world, 1, nullptr);
  SessionSimulator simulator = SmallRoomSession(*world, 2, 77);
  const auto steps = simulator.Run();
  Mapper mapper(MapperOptions{});
  // 0.3 m and 5 degrees off the docking pose.
  const Pose2 wrong = first.map.origin * Pose2(0.3, -0.2, 0.09);
  ASSERT_TRUE(mapper.LoadSession(first.map, wrong).ok());
  ASSERT_TRUE(mapper.SetMode(MapperMode::kLocalization).ok());
  EXPECT_EQ(mapper.mode(), MapperMode::kLocalization);
  double late_error = 0.0;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    ScanInput input;
    input.scan = steps[i].scan;
    input.odom_T_base = steps[i].odom_T_base;
    input.base_T_laser = simulator.base_T_laser();
    mapper.AddScan(input);
    if (i > steps.size() / 4) {
      const Pose2 estimate = mapper.map_T_odom() * steps[i].odom_T_base;
      late_error =
          std::max(late_error, (estimate.translation() - steps[i].map_T_base.translation()).norm());
    }
  }
  mapper.Finish();
  EXPECT_LT(late_error, 0.05);
  EXPECT_GT(mapper.stats().counters.at("localization_corrections"), 0u);
  // The map is exactly the loaded one.
  const SessionMap after = mapper.ExportSession();
  ASSERT_EQ(after.nodes.size(), first.map.nodes.size());
  for (const auto& [id, node] : first.map.nodes) {
    ASSERT_TRUE(after.nodes.count(id));
    EXPECT_EQ(after.nodes.at(id).map_T_node.x(), node.map_T_node.x());
    EXPECT_EQ(after.nodes.at(id).cloud.size(), node.cloud.size());
  }
  EXPECT_EQ(after.edges.size(), first.map.edges.size());
  const auto trajectory = mapper.Trajectory();
  EXPECT_LT((trajectory.back().pose.translation() - steps.back().map_T_base.translation()).norm(),
            0.05);
}

TEST(MultiSession, ModesSwitchBothWays) {
  const auto world = LoadWorld(std::string(LTM_CONFIG_DIR) + "/worlds/small_room.yaml");
  ASSERT_TRUE(world.ok());
  Mapper empty(MapperOptions{});
  EXPECT_FALSE(empty.SetMode(MapperMode::kLocalization).ok());  // no map yet
  EXPECT_FALSE(empty.OptimizeNow().ok());                       // nothing to optimise
  SimulationOptions simulation;
  simulation.duration_s = 90.0;
  SessionSimulator simulator(*world, 1, simulation, 5);
  const auto steps = simulator.Run();
  Mapper mapper(MapperOptions{});
  double max_error = 0.0;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (i == steps.size() / 3) {
      // Optimising on demand works while mapping, and is refused once the map is frozen.
      EXPECT_TRUE(mapper.OptimizeNow().ok());
      ASSERT_TRUE(mapper.SetMode(MapperMode::kLocalization).ok());
      EXPECT_FALSE(mapper.OptimizeNow().ok());
    }
    if (i == 2 * steps.size() / 3) {
      ASSERT_TRUE(mapper.SetMode(MapperMode::kMapping).ok());
    }
    ScanInput input;
    input.scan = steps[i].scan;
    input.odom_T_base = steps[i].odom_T_base;
    input.base_T_laser = simulator.base_T_laser();
    mapper.AddScan(input);
  }
  mapper.Finish();
  const auto trajectory = mapper.Trajectory();
  ASSERT_EQ(trajectory.size(), steps.size());
  for (std::size_t i = 0; i < steps.size(); ++i) {
    max_error = std::max(
        max_error, (trajectory[i].pose.translation() - steps[i].map_T_base.translation()).norm());
  }
  EXPECT_LT(max_error, 0.05);
  // Every edge joins existing nodes after the switches.
  const SessionMap map = mapper.ExportSession();
  for (const GraphEdge& e : map.edges) {
    EXPECT_TRUE(map.nodes.count(e.from) && map.nodes.count(e.to));
  }
}

TEST(MultiSession, LoadingAfterTheFirstScanIsRefused) {
  const auto world = LoadWorld(std::string(LTM_CONFIG_DIR) + "/worlds/small_room.yaml");
  ASSERT_TRUE(world.ok());
  const SessionResult first = MapSession(*world, 1, nullptr);
  Mapper mapper(MapperOptions{});
  ScanInput input;
  input.scan.ranges.assign(10, 1.0f);
  mapper.AddScan(input);
  EXPECT_FALSE(mapper.LoadSession(first.map, std::nullopt).ok());
  Mapper empty(MapperOptions{});
  EXPECT_FALSE(empty.LoadSession(SessionMap{}, std::nullopt).ok());
}

TEST(MultiSession, OptimizingOnDemandAlignsNoNodeAgain) {
  // Every node is searched for closures when it is made; optimising on demand only votes on what
  // is still pending (without the final sweep, which searches every node again on purpose).
  const auto world = LoadWorld(std::string(LTM_CONFIG_DIR) + "/worlds/small_room.yaml");
  ASSERT_TRUE(world.ok());
  SimulationOptions simulation;
  simulation.duration_s = 90.0;
  SessionSimulator simulator(*world, 1, simulation, 5);
  MapperOptions options;
  options.loop_closing.final_sweep = false;
  Mapper mapper(options);
  for (const auto& step : simulator.Run()) {
    ScanInput input;
    input.scan = step.scan;
    input.odom_T_base = step.odom_T_base;
    input.base_T_laser = simulator.base_T_laser();
    mapper.AddScan(input);
  }
  auto alignments = [&mapper] {
    const auto it = mapper.stats().counters.find("loop_closure_alignments");
    return it == mapper.stats().counters.end() ? 0 : it->second;
  };
  const auto made = alignments();
  ASSERT_GT(made, 0u);  // the room is revisited all the time
  ASSERT_TRUE(mapper.OptimizeNow().ok());
  EXPECT_EQ(alignments(), made);
  ASSERT_TRUE(mapper.OptimizeNow().ok());
  EXPECT_EQ(alignments(), made);
}

}  // namespace
}  // namespace longterm_mapper2d
