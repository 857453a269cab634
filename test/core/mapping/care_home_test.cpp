// The care home (config/worlds/care_home.yaml) mapped over three simulated sessions, each on the
// map the previous one left: people walking in the corridors and the day room, furniture and doors
// that change between sessions. Scored against the simulator's truth (ALGORITHMS.md, issue 7's
// criteria): map precision and recall, the old places of moved objects, trajectory error, and the
// size of the graph.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>

#include "longterm_mapper2d/core/evaluation/map_comparison.h"
#include "longterm_mapper2d/core/map/grid_renderer.h"
#include "longterm_mapper2d/core/mapping/mapper.h"
#include "longterm_mapper2d/core/mapping/merge_extent.h"
#include "longterm_mapper2d/core/simulation/session_simulator.h"
#include "testing/simulated_mapping.h"

namespace longterm_mapper2d {
namespace {

struct CareHomeSession {
  SessionMap map;
  OccupancyGrid grid;
  MapComparison quality;
  double rmse_m = 0.0;
  int nodes = 0;
  double max_reach_m = 0.0;  // the farthest waypoint of any node from its node's origin
  std::uint64_t members_beyond_extent = 0;
};

// One whole patrol (430 s) of session `session`, on top of `previous` when given.
CareHomeSession MapCareHomeSession(const World& world, int session, const SessionMap* previous,
                                   std::uint64_t seed,
                                   const MapperOptions& options = MapperOptions{}) {
  SimulationOptions simulation;
  simulation.duration_s = 430.0;
  SessionSimulator simulator(world, session, simulation, seed);
  const auto steps = simulator.Run();
  Mapper mapper(options);
  if (previous) {
    EXPECT_TRUE(mapper.LoadSession(*previous, std::nullopt).ok());
  }
  test_support::MapSimulatedSteps(steps, simulator.base_T_laser(), mapper);
  CareHomeSession result;
  const std::vector<double> errors = test_support::PositionErrors(mapper, steps);
  EXPECT_EQ(errors.size(), steps.size());
  double sum_sq = 0.0;
  for (const double error_m : errors) sum_sq += error_m * error_m;
  result.rmse_m = std::sqrt(sum_sq / errors.size());
  auto grid = RenderOccupancyGrid(mapper.WaypointScans(), mapper.options().grid);
  EXPECT_TRUE(grid.ok()) << grid.status().message();
  result.grid = *grid;
  const OccupancyGrid truth = RasterizeWorld(world, session, result.grid.resolution_m);
  auto quality = CompareMaps(result.grid, truth);
  EXPECT_TRUE(quality.ok()) << quality.status().message();
  result.quality = *quality;
  result.nodes = static_cast<int>(mapper.graph().nodes().size());
  result.map = mapper.ExportSession();
  for (const auto& [id, node] : result.map.nodes) {
    result.max_reach_m = std::max(result.max_reach_m, ReachFrom(node, node));
  }
  const auto beyond = mapper.stats().counters.find("merge_members_beyond_extent");
  if (beyond != mapper.stats().counters.end()) result.members_beyond_extent = beyond->second;
  std::printf(
      "session %d, seed %llu: precision %.3f (on a true cell %.3f) recall %.3f phantom cells "
      "%lld, trajectory RMSE %.3f m, %d nodes\n",
      session, static_cast<unsigned long long>(seed), result.quality.precision,
      result.quality.precision_on_truth, result.quality.recall,
      static_cast<long long>(result.quality.phantom), result.rmse_m, result.nodes);
  return result;
}

// The map as its points: every node's cloud in the map frame, rasterised onto the truth's lattice
// (occupied where a point falls, unknown elsewhere). This is what free-space merging acts on; the
// grid of the other tests is rendered from raw scans.
MapComparison CloudMapQuality(const SessionMap& map, const OccupancyGrid& truth) {
  OccupancyGrid grid = truth;
  std::fill(grid.cells.begin(), grid.cells.end(), -1);
  for (const auto& [id, node] : map.nodes) {
    for (const RichPoint& p : node.cloud) {
      const Eigen::Vector2i cell = grid.WorldToCell(node.map_T_node * p.point_m);
      if (cell.x() < 0 || cell.y() < 0 || cell.x() >= grid.width || cell.y() >= grid.height)
        continue;
      grid.at(cell.x(), cell.y()) = 100;
    }
  }
  auto quality = CompareMaps(grid, truth);
  EXPECT_TRUE(quality.ok()) << quality.status().message();
  return quality.ok() ? *quality : MapComparison{};
}

double DistanceToSegment(const Eigen::Vector2d& p, const Segment& s) {
  const Eigen::Vector2d d = s.b_m - s.a_m;
  const double t =
      d.squaredNorm() > 0.0 ? std::clamp((p - s.a_m).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (s.a_m + t * d)).norm();
}

// Of the places where objects of session `before` stood that are gone in session `after`
// (sampled every 5 cm, away from anything still there), the fraction the map shows occupied.
double OccupiedWhereObjectsLeft(const World& world, int before, int after, const OccupancyGrid& map,
                                int* samples) {
  const auto remaining = world.StaticSegments(after);
  int occupied = 0;
  *samples = 0;
  for (const SemiStaticObject& object : world.objects) {
    if (!object.PresentIn(before) || object.PresentIn(after)) continue;
    for (const Segment& segment : object.segments) {
      const double length = (segment.b_m - segment.a_m).norm();
      for (double s = 0.0; s <= length; s += 0.05) {
        const Eigen::Vector2d p = segment.a_m + (segment.b_m - segment.a_m) * (s / length);
        bool near_remaining = false;
        for (const Segment& r : remaining) near_remaining |= DistanceToSegment(p, r) < 0.15;
        if (near_remaining) continue;
        const Eigen::Vector2i cell = map.WorldToCell(p);
        if (cell.x() < 0 || cell.y() < 0 || cell.x() >= map.width || cell.y() >= map.height)
          continue;
        ++*samples;
        if (map.at(cell.x(), cell.y()) >= 65) ++occupied;
      }
    }
  }
  return *samples > 0 ? static_cast<double>(occupied) / *samples : 0.0;
}

// Fifteen people walk the corridors and the day room while the robot patrols. A person walking
// along a corridor ahead of the robot is what scan matching fears most; the tracker registers only
// against surfaces seen in place. Five realisations (people's timing against the robot's, odometry
// noise, range noise) of session 1, each mapped from scratch.
TEST(CareHome, PeopleWalkingByStayOutOfTheMap) {
  const auto world = LoadWorld(std::string(LTM_CONFIG_DIR) + "/worlds/care_home.yaml");
  ASSERT_TRUE(world.ok()) << world.status().message();
  int good = 0;
  for (std::uint64_t seed = 11; seed <= 15; ++seed) {
    const CareHomeSession run = MapCareHomeSession(*world, 1, nullptr, seed);
    if (run.quality.precision >= 0.97 && run.rmse_m < 0.05) ++good;
  }
  // Measured: 5 of 5 (RMSE 1.2-3.4 cm, precision 0.999-1.000; without tolerance, on a true cell
  // itself, 0.907-0.999, falling as the RMSE grows). Until the truth raster put a wall on a grid
  // line into the cells on both sides it was half a cell off for most walls, and precision read
  // 0.968-0.999 (seed 14 below 0.97). Of seeds 1-7 two once drifted 7 and 14 cm along the cross
  // corridor, where a nurse walks towards the robot; hence 4 of 5.
  EXPECT_GE(good, 4);
}

// The same session mapped with the free-space merger and with plain accumulation
// (merger.free_space_reasoning: false): the points of the map (the node clouds) keep far fewer
// phantoms (people's trails) with it.
TEST(CareHome, FreeSpaceMergingKeepsPeopleOutOfTheMapClouds) {
  const auto world = LoadWorld(std::string(LTM_CONFIG_DIR) + "/worlds/care_home.yaml");
  ASSERT_TRUE(world.ok()) << world.status().message();
  const OccupancyGrid truth = RasterizeWorld(*world, 1, 0.05);
  const CareHomeSession merged = MapCareHomeSession(*world, 1, nullptr, 11);
  MapperOptions accumulate;
  accumulate.merger.free_space_reasoning = false;
  const CareHomeSession accumulated = MapCareHomeSession(*world, 1, nullptr, 11, accumulate);
  const MapComparison with = CloudMapQuality(merged.map, truth);
  const MapComparison without = CloudMapQuality(accumulated.map, truth);
  std::printf(
      "map clouds: free-space merging %lld phantom cells, precision %.3f; accumulation "
      "%lld phantom cells, precision %.3f\n",
      static_cast<long long>(with.phantom), with.precision, static_cast<long long>(without.phantom),
      without.precision);
  // Measured: 190 against 3315 phantom cells (0.057x), precision 0.981 against 0.768 (with the
  // truth raster of before, half a cell off on grid lines: 191 / 3317, 0.981 / 0.754). Before the
  // finished nodes lost their seen-moving points 347 (0.105x) and 0.966; before the last node was
  // cleaned by the next stretch's scans 797 and 0.926.
  EXPECT_LE(with.phantom, 0.10 * without.phantom);
  EXPECT_GE(with.precision, 0.97);
  EXPECT_GT(with.precision, without.precision);
}

// Furniture added, removed and moved, doors shut and opened between sessions; each session is
// mapped on the map the previous one left.
TEST(CareHome, FurnitureChangesAreTakenInAndTheGraphStaysTheSizeOfTheFloor) {
  const auto world = LoadWorld(std::string(LTM_CONFIG_DIR) + "/worlds/care_home.yaml");
  ASSERT_TRUE(world.ok()) << world.status().message();
  const CareHomeSession first = MapCareHomeSession(*world, 1, nullptr, 1);
  const CareHomeSession second = MapCareHomeSession(*world, 2, &first.map, 2);
  EXPECT_GE(second.quality.precision, 0.95);
  EXPECT_GE(second.quality.recall, 0.90);
  EXPECT_LT(second.rmse_m, 0.05);
  int samples = 0;
  const double left_occupied = OccupiedWhereObjectsLeft(*world, 1, 2, second.grid, &samples);
  std::printf("places objects left after session 1: %d cells, %.3f still occupied\n", samples,
              left_occupied);
  EXPECT_GT(samples, 50);
  EXPECT_LE(left_occupied, 0.1);  // measured 0.000

  const CareHomeSession third = MapCareHomeSession(*world, 3, &second.map, 3);
  EXPECT_LE(third.nodes, 1.3 * first.nodes);
  EXPECT_GE(third.quality.precision, 0.95);
  EXPECT_LT(third.rmse_m, 0.05);
}

// maintenance.merge_max_extent_m: merged local maps stay local. Unbounded, the patrol's survivors
// hold scans up to 19-22 m from their origins.
TEST(CareHome, MergedLocalMapsStayWithinTheirExtentWhenBounded) {
  const auto world = LoadWorld(std::string(LTM_CONFIG_DIR) + "/worlds/care_home.yaml");
  ASSERT_TRUE(world.ok()) << world.status().message();
  MapperOptions bounded;
  bounded.maintenance.merge_max_extent_m = 8.0;
  const CareHomeSession unbounded_session = MapCareHomeSession(*world, 1, nullptr, 1);
  const CareHomeSession bounded_session = MapCareHomeSession(*world, 1, nullptr, 1, bounded);
  EXPECT_GT(unbounded_session.max_reach_m, 12.0);
  EXPECT_EQ(unbounded_session.members_beyond_extent, 0u);
  EXPECT_LE(bounded_session.max_reach_m, 8.0);
  EXPECT_GT(bounded_session.members_beyond_extent, 0u);
  EXPECT_LT(bounded_session.rmse_m, 0.05);
  EXPECT_GE(bounded_session.quality.precision, 0.95);
}

}  // namespace
}  // namespace longterm_mapper2d
