#include <gtest/gtest.h>

#include <cmath>

#include "longterm_mapper2d/core/simulation/session_simulator.h"
#include "longterm_mapper2d/core/simulation/world.h"

namespace longterm_mapper2d {
namespace {

const char kRoom[] = R"(
name: test_room
robot: {speed_mps: 0.5, turn_rate_radps: 1.0, route: [[1, 1], [4, 1], [4, 3], [1, 3]]}
walls: [[0, 0, 5, 0], [5, 0, 5, 4], [5, 4, 0, 4], [0, 4, 0, 0]]
objects:
  - {name: crate, sessions: [2], boxes: [[2, 1.5, 3, 2.5]]}
people:
  - {speed_mps: 1.0, path: [[0.5, 0.5], [4.5, 0.5]]}
)";

TEST(RayCasting, HitsSegmentsAndCirclesAtTheRightRange) {
  const std::vector<Segment> walls = BoxSegments(0, 0, 10, 10);
  const Eigen::Vector2d origin(2, 5);
  EXPECT_NEAR(CastRay(walls, {}, origin, 0.0, 30.0), 8.0, 1e-9);
  EXPECT_NEAR(CastRay(walls, {}, origin, M_PI, 30.0), 2.0, 1e-9);
  EXPECT_NEAR(CastRay(walls, {}, origin, M_PI / 4, 30.0), 5.0 * std::sqrt(2.0), 1e-9);
  // A person (circle of radius 0.5 at x = 5) in front of the wall.
  EXPECT_NEAR(CastRay(walls, {Eigen::Vector3d(5, 5, 0.5)}, origin, 0.0, 30.0), 2.5, 1e-9);
  // Beyond max range: no return.
  EXPECT_TRUE(std::isinf(CastRay(walls, {}, origin, 0.0, 5.0)));
  EXPECT_TRUE(std::isinf(CastRay({}, {}, origin, 0.0, 30.0)));
}

TEST(World, LoadsAndAppliesSessionObjects) {
  const auto world = ParseWorld(kRoom);
  ASSERT_TRUE(world.ok()) << world.status().message();
  EXPECT_EQ(world->StaticSegments(1).size(), 4u);
  EXPECT_EQ(world->StaticSegments(2).size(), 8u);
  EXPECT_NEAR(world->people[0].PositionAt(2.0).x(), 2.5, 1e-9);
  // Walks back along the closed path.
  EXPECT_NEAR(world->people[0].PositionAt(6.0).x(), 2.5, 1e-9);
}

TEST(World, ErrorsNameTheKey) {
  auto world = ParseWorld("robot: {route: [[0, 0], [1, 1]]}\nwals: []\n");
  ASSERT_FALSE(world.ok());
  EXPECT_NE(world.status().message().find("wals: unknown key"), std::string::npos);
  world = ParseWorld("robot: {route: [[0, 0], [1]]}\n");
  ASSERT_FALSE(world.ok());
  EXPECT_NE(world.status().message().find("robot/route[1]"), std::string::npos);
  world = ParseWorld("walls: [[0, 0, 1, 1]]\n");
  ASSERT_FALSE(world.ok());
  EXPECT_NE(world.status().message().find("robot"), std::string::npos);
}

TEST(World, ShippedWorldsLoad) {
  for (const char* name : {"small_room", "care_home"}) {
    const auto world = LoadWorld(std::string(LTM_CONFIG_DIR) + "/worlds/" + name + ".yaml");
    EXPECT_TRUE(world.ok()) << name << ": " << world.status().message();
  }
}

TEST(World, TheCareHomeIsAFloorWithPeopleAndFurnitureThatMoves) {
  const auto world = LoadWorld(std::string(LTM_CONFIG_DIR) + "/worlds/care_home.yaml");
  ASSERT_TRUE(world.ok()) << world.status().message();
  Eigen::Vector2d low(1e9, 1e9), high(-1e9, -1e9);
  for (const Segment& wall : world->walls) {
    for (const Eigen::Vector2d& p : {wall.a_m, wall.b_m}) {
      low = low.cwiseMin(p);
      high = high.cwiseMax(p);
    }
  }
  EXPECT_GE(high.x() - low.x(), 40.0);
  EXPECT_GE(high.y() - low.y(), 30.0);
  EXPECT_EQ(world->people.size(), 15u);
  // Furniture differs between every pair of consecutive sessions.
  auto signature = [&](int session) {
    std::vector<double> values;
    for (const Segment& s : world->StaticSegments(session)) {
      values.insert(values.end(), {s.a_m.x(), s.a_m.y(), s.b_m.x(), s.b_m.y()});
    }
    return values;
  };
  for (int session = 1; session < 3; ++session) {
    EXPECT_NE(signature(session), signature(session + 1))
        << "sessions " << session << ", " << session + 1;
  }
}

TEST(SessionSimulator, IsDeterministicForASeedAndDiffersAcrossSeeds) {
  const auto world = ParseWorld(kRoom);
  ASSERT_TRUE(world.ok());
  SimulationOptions options;
  options.duration_s = 20.0;
  const auto a = SessionSimulator(*world, 1, options, 7).Run();
  const auto b = SessionSimulator(*world, 1, options, 7).Run();
  const auto c = SessionSimulator(*world, 1, options, 8).Run();
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), 200u);
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].scan.ranges, b[i].scan.ranges);
    EXPECT_EQ(a[i].odom_T_base.vector(), b[i].odom_T_base.vector());
    differs |= a[i].scan.ranges != c[i].scan.ranges;
  }
  EXPECT_TRUE(differs);
}

TEST(SessionSimulator, AnInterlacedLaserStartsEveryOtherScanHalfABeamLater) {
  const auto world = ParseWorld(kRoom);
  ASSERT_TRUE(world.ok());
  SimulationOptions options;
  options.duration_s = 2.0;
  options.beams = 181;
  options.fov_rad = M_PI;
  const auto plain = SessionSimulator(*world, 1, options, 7).Run();
  options.interlaced = true;
  const auto interlaced = SessionSimulator(*world, 1, options, 7).Run();
  ASSERT_EQ(plain.size(), interlaced.size());
  ASSERT_GE(plain.size(), 4u);
  const double increment = M_PI / 180.0;
  for (std::size_t i = 0; i < plain.size(); ++i) {
    EXPECT_DOUBLE_EQ(plain[i].scan.angle_min_rad, -M_PI / 2.0);
    EXPECT_DOUBLE_EQ(interlaced[i].scan.angle_min_rad,
                     -M_PI / 2.0 + (i % 2 == 1 ? 0.5 * increment : 0.0));
    EXPECT_DOUBLE_EQ(interlaced[i].scan.angle_increment_rad, increment);
    // Even scans see what the plain laser sees; odd ones look between its beams.
    if (i % 2 == 0) EXPECT_EQ(interlaced[i].scan.ranges, plain[i].scan.ranges);
  }
}

TEST(SessionSimulator, OdometrySlipMatchesTheNoiseModel) {
  // A long straight corridor: the odometry error after driving it estimates the slip sigma.
  World world;
  world.walls = BoxSegments(-1, -2, 1001, 2);
  world.route_m = {Eigen::Vector2d(0, 0), Eigen::Vector2d(1000, 0)};
  world.robot_speed_mps = 1.0;
  SimulationOptions options;
  options.duration_s = 100.0;
  options.rate_hz = 10.0;
  options.beams = 2;
  options.slip_per_m = 0.05;
  options.drift_rad_per_m = 0.0;
  options.rotation_per_m = 0.0;
  double sum = 0.0, sum_sq = 0.0;
  const int runs = 40;
  for (int seed = 0; seed < runs; ++seed) {
    const auto steps = SessionSimulator(world, 1, options, seed).Run();
    const double error = steps.back().odom_T_base.x() - steps.back().map_T_base.x();
    sum += error;
    sum_sq += error * error;
  }
  // 1000 steps of 0.1 m, each scaled by N(1, 0.05): error sigma = 0.05 * 0.1 * sqrt(1000).
  const double expected_sigma = 0.05 * 0.1 * std::sqrt(1000.0);
  const double mean = sum / runs;
  const double sigma = std::sqrt(sum_sq / runs - mean * mean);
  EXPECT_NEAR(mean, 0.0, 3.0 * expected_sigma / std::sqrt(runs));
  EXPECT_NEAR(sigma, expected_sigma, 0.35 * expected_sigma);
}

TEST(SessionSimulator, TruthRasterMarksWallsOccupied) {
  const auto world = ParseWorld(kRoom);
  ASSERT_TRUE(world.ok());
  const OccupancyGrid grid = RasterizeWorld(*world, 2, 0.05);
  const Eigen::Vector2i wall = grid.WorldToCell(Eigen::Vector2d(2.5, 0.0));
  const Eigen::Vector2i crate = grid.WorldToCell(Eigen::Vector2d(2.0, 2.0));
  const Eigen::Vector2i free = grid.WorldToCell(Eigen::Vector2d(1.0, 1.0));
  EXPECT_EQ(grid.at(wall.x(), wall.y()), 100);
  EXPECT_EQ(grid.at(crate.x(), crate.y()), 100);
  EXPECT_EQ(grid.at(free.x(), free.y()), 0);
  const OccupancyGrid session1 = RasterizeWorld(*world, 1, 0.05);
  const Eigen::Vector2i crate1 = session1.WorldToCell(Eigen::Vector2d(2.0, 2.0));
  EXPECT_EQ(session1.at(crate1.x(), crate1.y()), 0);
}

TEST(SessionSimulator, TruthRasterPutsAWallOnAGridLineIntoTheCellsOnBothSides) {
  // Walls at y = 0 and y = 4 lie on grid lines of a 0.05 m grid; the wall at y = 2.02 and the
  // crate's sides inside cells. Returns from either side of a wall on a grid line land on both
  // sides of it, so both cells are the wall.
  auto world = ParseWorld(kRoom);
  ASSERT_TRUE(world.ok()) << world.status().message();
  world->walls.push_back({Eigen::Vector2d(0.0, 2.02), Eigen::Vector2d(1.0, 2.02)});
  const OccupancyGrid grid = RasterizeWorld(*world, 1, 0.05);
  auto occupied_rows = [&](double x_m, double y_lo_m, double y_hi_m) {
    std::vector<double> rows;
    for (double y = y_lo_m; y < y_hi_m; y += 0.05) {
      const Eigen::Vector2i c = grid.WorldToCell(Eigen::Vector2d(x_m, y));
      if (grid.at(c.x(), c.y()) == 100) rows.push_back(grid.CellCenter(c.x(), c.y()).y());
    }
    return rows;
  };
  const auto on_line = occupied_rows(2.51, -0.2126, 0.2);
  ASSERT_EQ(on_line.size(), 2u);
  EXPECT_NEAR(on_line[0], -0.025, 1e-9);
  EXPECT_NEAR(on_line[1], 0.025, 1e-9);
  const auto top = occupied_rows(2.51, 3.7874, 4.2);
  ASSERT_EQ(top.size(), 2u);
  EXPECT_NEAR(top[0], 3.975, 1e-9);
  EXPECT_NEAR(top[1], 4.025, 1e-9);
  const auto inside = occupied_rows(0.51, 1.7874, 2.2);
  ASSERT_EQ(inside.size(), 1u);
  EXPECT_NEAR(inside[0], 2.025, 1e-9);
}

}  // namespace
}  // namespace longterm_mapper2d
