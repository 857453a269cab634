#include "longterm_mapper2d/core/map/grid_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "longterm_mapper2d/core/config/mapper_options.h"
#include "longterm_mapper2d/core/config/yaml_options.h"

namespace longterm_mapper2d {
namespace {

constexpr double kHalfSide = 1.98;  // walls at x, y = +-1.98 (inside cells, not on boundaries)

LaserScan MakeScan(int beams, double angle_min, double increment, double range_max = 20.0) {
  LaserScan scan;
  scan.angle_min_rad = angle_min;
  scan.angle_increment_rad = increment;
  scan.range_min_m = 0.05;
  scan.range_max_m = range_max;
  scan.ranges.assign(beams, std::numeric_limits<float>::infinity());
  return scan;
}

// Distance from `p` along `angle` to the walls of the square room [-h, h]^2.
double RangeToBox(const Eigen::Vector2d& p, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  double t = std::numeric_limits<double>::infinity();
  if (c > 1e-12) t = std::min(t, (kHalfSide - p.x()) / c);
  if (c < -1e-12) t = std::min(t, (-kHalfSide - p.x()) / c);
  if (s > 1e-12) t = std::min(t, (kHalfSide - p.y()) / s);
  if (s < -1e-12) t = std::min(t, (-kHalfSide - p.y()) / s);
  return t;
}

PosedScan BoxRoomScan(const Pose2& map_T_laser) {
  PosedScan posed;
  posed.map_T_laser = map_T_laser;
  posed.scan = MakeScan(720, -M_PI, 2 * M_PI / 720);
  for (int i = 0; i < 720; ++i) {
    posed.scan.ranges[i] = static_cast<float>(
        RangeToBox(map_T_laser.translation(), map_T_laser.theta() + posed.scan.BeamAngle(i)));
  }
  return posed;
}

int8_t CellAt(const OccupancyGrid& grid, double x, double y) {
  const Eigen::Vector2i c = grid.WorldToCell(Eigen::Vector2d(x, y));
  EXPECT_TRUE(grid.InBounds(c.x(), c.y())) << x << ", " << y;
  return grid.InBounds(c.x(), c.y()) ? grid.at(c.x(), c.y()) : -2;
}

TEST(RenderOccupancyGrid, BoxRoomHasOccupiedWallsFreeInsideUnknownOutside) {
  GridOptions options;
  options.resolution_m = 0.1;
  const std::vector<PosedScan> scans = {BoxRoomScan(Pose2(0.013, 0.021, 0.3)),
                                        BoxRoomScan(Pose2(-0.7, 0.45, -1.0))};
  GridRenderStats stats;
  const auto grid = RenderOccupancyGrid(scans, options, &stats);
  ASSERT_TRUE(grid.ok()) << grid.status().message();
  EXPECT_EQ(stats.scans_used, 2);
  EXPECT_EQ(stats.beams_cast, 1440);
  // Bounds: walls plus the margin, on the resolution lattice.
  EXPECT_LE(grid->origin_m.x(), -kHalfSide - options.margin_m + 1e-9);
  EXPECT_GE(grid->MaxCorner().x(), kHalfSide + options.margin_m - 1e-9);
  EXPECT_LT(grid->width, 56);

  for (double u = -1.85; u <= 1.85; u += 0.1) {
    EXPECT_EQ(CellAt(*grid, kHalfSide, u), 100) << "east wall at " << u;
    EXPECT_EQ(CellAt(*grid, -kHalfSide, u), 100) << "west wall at " << u;
    EXPECT_EQ(CellAt(*grid, u, kHalfSide), 100) << "north wall at " << u;
    EXPECT_EQ(CellAt(*grid, u, -kHalfSide), 100) << "south wall at " << u;
  }
  for (double x = -1.75; x <= 1.75; x += 0.1) {
    for (double y = -1.75; y <= 1.75; y += 0.1) {
      EXPECT_EQ(CellAt(*grid, x, y), 0) << "inside at " << x << ", " << y;
    }
  }
  for (double u = -2.3; u <= 2.3; u += 0.1) {
    EXPECT_EQ(CellAt(*grid, 2.25, u), -1);
    EXPECT_EQ(CellAt(*grid, u, -2.25), -1);
  }
}

TEST(RenderOccupancyGrid, NoReturnBeamsClearOnlyUpToTheCap) {
  GridOptions options;
  options.resolution_m = 0.05;
  options.free_space_max_range_m = 1.0;
  PosedScan posed;
  posed.map_T_laser = Pose2(0.01, 0.01, 0.0);
  posed.scan = MakeScan(360, -M_PI, 2 * M_PI / 360, 8.0);
  // Half the beams report inf, half report the range_max value (also no return).
  for (int i = 0; i < 360; i += 2) posed.scan.ranges[i] = 8.0f;
  const auto grid = RenderOccupancyGrid({posed}, options);
  ASSERT_TRUE(grid.ok()) << grid.status().message();
  int occupied = 0;
  for (const int8_t v : grid->cells) occupied += v == 100;
  EXPECT_EQ(occupied, 0);
  EXPECT_EQ(CellAt(*grid, 0.9, 0.0), 0);
  EXPECT_EQ(CellAt(*grid, 0.0, -0.9), 0);
  EXPECT_EQ(CellAt(*grid, -0.6, 0.6), 0);
  EXPECT_EQ(CellAt(*grid, 1.2, 0.0), -1);
  EXPECT_EQ(CellAt(*grid, 0.0, 1.3), -1);

  // With the cap at 0, no-return beams carry no information at all.
  options.free_space_max_range_m = 0.0;
  const auto silent = RenderOccupancyGrid({posed}, options);
  ASSERT_TRUE(silent.ok());
  for (const int8_t v : silent->cells) ASSERT_EQ(v, -1);
}

TEST(RenderOccupancyGrid, LaserPoseAndBeamAnglesPlaceTheHit) {
  GridOptions options;
  options.resolution_m = 0.05;
  PosedScan posed;
  posed.map_T_laser = Pose2(5.01, -3.01, M_PI / 2);
  posed.scan = MakeScan(3, -0.1, 0.1);
  posed.scan.ranges = {std::numeric_limits<float>::quiet_NaN(), 1.0f, 0.01f};  // NaN, hit, short
  GridRenderStats stats;
  const auto grid = RenderOccupancyGrid({posed}, options, &stats);
  ASSERT_TRUE(grid.ok()) << grid.status().message();
  EXPECT_EQ(stats.beams_cast, 1);
  EXPECT_EQ(CellAt(*grid, 5.01, -2.01), 100);  // straight ahead = +y in the map
  EXPECT_EQ(CellAt(*grid, 5.01, -2.5), 0);
  EXPECT_EQ(CellAt(*grid, 5.06, -2.01), -1);
  int occupied = 0, free = 0;
  for (const int8_t v : grid->cells) {
    occupied += v == 100;
    free += v == 0;
  }
  EXPECT_EQ(occupied, 1);
  EXPECT_EQ(free, 20);  // the 20 cells from y = -3.05 to -2.05 on the ray
}

TEST(RenderOccupancyGrid, AHitIsNotErasedByAnotherBeamOfTheSameScan) {
  GridOptions options;
  options.resolution_m = 0.1;
  PosedScan posed;
  posed.map_T_laser = Pose2(0.05, 0.05, 0.0);
  posed.scan = MakeScan(2, 0.0, 1e-3);
  // Beam 0 ends in the cell at x = 1.05; beam 1 passes through it to x = 2.05.
  posed.scan.ranges = {1.0f, 2.0f};
  const auto grid = RenderOccupancyGrid({posed}, options);
  ASSERT_TRUE(grid.ok());
  EXPECT_EQ(CellAt(*grid, 1.05, 0.05), 100);
  EXPECT_EQ(CellAt(*grid, 2.05, 0.05), 100);
  EXPECT_EQ(CellAt(*grid, 1.55, 0.05), 0);

  // Across scans the evidence accumulates: one hit (+0.85) and three misses (-1.8) give a free
  // cell (p = 0.28), where one hit and two misses (p = 0.41) stay undecided.
  PosedScan through = posed;
  through.scan.ranges = {2.0f, 2.0f};
  const auto undecided = RenderOccupancyGrid({posed, through, through}, options);
  ASSERT_TRUE(undecided.ok());
  EXPECT_EQ(CellAt(*undecided, 1.05, 0.05), 41);
  const auto updated = RenderOccupancyGrid({posed, through, through, through}, options);
  ASSERT_TRUE(updated.ok());
  EXPECT_EQ(CellAt(*updated, 1.05, 0.05), 0);
}

TEST(RenderOccupancyGrid, BadInputIsReportedOrSkipped) {
  GridOptions options;
  EXPECT_FALSE(RenderOccupancyGrid({}, options).ok());
  PosedScan bad_pose = BoxRoomScan(Pose2());
  bad_pose.map_T_laser = Pose2(NAN, 0.0, 0.0);
  PosedScan bad_geometry = BoxRoomScan(Pose2());
  bad_geometry.scan.angle_increment_rad = -0.1;
  EXPECT_FALSE(RenderOccupancyGrid({bad_pose, bad_geometry}, options).ok());
  GridRenderStats stats;
  ASSERT_TRUE(RenderOccupancyGrid({bad_pose, BoxRoomScan(Pose2())}, options, &stats).ok());
  EXPECT_EQ(stats.scans_skipped, 1);
  EXPECT_EQ(stats.scans_used, 1);

  // A pose far away would need a huge grid: refused, not allocated.
  PosedScan far = BoxRoomScan(Pose2(1e6, 1e6, 0.0));
  const auto huge = RenderOccupancyGrid({BoxRoomScan(Pose2()), far}, options);
  ASSERT_FALSE(huge.ok());
  EXPECT_NE(huge.status().message().find("max_cells"), std::string::npos);

  GridOptions wrong;
  wrong.free_threshold = 0.7;
  const auto rejected = RenderOccupancyGrid({BoxRoomScan(Pose2())}, wrong);
  ASSERT_FALSE(rejected.ok());
  EXPECT_NE(rejected.status().message().find("free_threshold"), std::string::npos);
}

TEST(GridOptions, LoadAsTheGridSectionOfMapperOptions) {
  MapperOptions options;
  ASSERT_TRUE(
      LoadOptionsFromYamlString("grid:\n  resolution_m: 0.1\n  max_cells: 5000\n", options).ok());
  EXPECT_DOUBLE_EQ(options.grid.resolution_m, 0.1);
  EXPECT_EQ(options.grid.max_cells, 5000);
  MapperOptions bad;
  const Status s = LoadOptionsFromYamlString("grid:\n  resolution_m: -1\n  typo: 1\n", bad);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("grid/resolution_m"), std::string::npos);
  EXPECT_NE(s.message().find("grid/typo"), std::string::npos);
}

}  // namespace
}  // namespace longterm_mapper2d
