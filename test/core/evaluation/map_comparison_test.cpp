#include "longterm_mapper2d/core/evaluation/map_comparison.h"

#include <gtest/gtest.h>

#include <functional>

namespace longterm_mapper2d {
namespace {

// A grid whose cells take `value(centre)`.
OccupancyGrid GridFrom(double res, int width, int height, const Eigen::Vector2d& origin,
                       const std::function<int8_t(const Eigen::Vector2d&)>& value) {
  OccupancyGrid grid = OccupancyGrid::Filled(res, width, height, origin);
  for (int iy = 0; iy < height; ++iy) {
    for (int ix = 0; ix < width; ++ix) grid.at(ix, iy) = value(grid.CellCenter(ix, iy));
  }
  return grid;
}

// Truth: a wall in column 5 of a 10 x 10 grid of 1 m cells.
OccupancyGrid WallTruth() {
  OccupancyGrid truth = OccupancyGrid::Filled(1.0, 10, 10, Eigen::Vector2d::Zero(), 0);
  for (int y = 0; y < 10; ++y) truth.at(5, y) = 100;
  return truth;
}

// Map: rows 0..4 observed, hits at (5,2) exact, (6,3) one cell off, (7,4) two off, (2,2) three
// off and (9,9) four off (the only observed cell of the upper half).
OccupancyGrid HandMap() {
  OccupancyGrid map = OccupancyGrid::Filled(1.0, 10, 10, Eigen::Vector2d::Zero());
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 10; ++x) map.at(x, y) = 0;
  }
  map.at(5, 2) = 100;
  map.at(6, 3) = 100;
  map.at(7, 4) = 70;  // above the occupied threshold (65)
  map.at(2, 2) = 100;
  map.at(9, 9) = 100;
  map.at(4, 4) = 50;  // observed but not occupied
  return map;
}

TEST(CompareMaps, HandMadeGridsGiveHandCountedFigures) {
  RgbImage diff;
  const auto result = CompareMaps(HandMap(), WallTruth(), {}, &diff);
  ASSERT_TRUE(result.ok()) << result.status().message();
  EXPECT_EQ(result->map_occupied, 5);
  EXPECT_EQ(result->correct, 2);
  EXPECT_EQ(result->on_truth, 1);  // (5, 2)
  EXPECT_EQ(result->phantom, 2);
  EXPECT_DOUBLE_EQ(result->precision, 0.4);
  EXPECT_DOUBLE_EQ(result->precision_on_truth, 0.2);
  EXPECT_DOUBLE_EQ(result->phantom_fraction, 0.4);
  EXPECT_EQ(result->truth_occupied, 10);
  EXPECT_EQ(result->truth_observed, 5);  // (5, 0..4)
  EXPECT_EQ(result->recalled, 4);        // (5, 0) is two cells from the nearest hit
  EXPECT_DOUBLE_EQ(result->recall, 0.8);

  ASSERT_EQ(diff.width, 10);
  ASSERT_EQ(diff.height, 10);
  auto pixel = [&](int x, int y) {  // grid cell -> image pixel (top row first)
    const std::size_t i = 3 * (static_cast<std::size_t>(9 - y) * 10 + x);
    return std::array<uint8_t, 3>{diff.rgb[i], diff.rgb[i + 1], diff.rgb[i + 2]};
  };
  EXPECT_EQ(pixel(5, 2), (std::array<uint8_t, 3>{0, 170, 0}));      // correct
  EXPECT_EQ(pixel(9, 9), (std::array<uint8_t, 3>{255, 0, 0}));      // phantom
  EXPECT_EQ(pixel(7, 4), (std::array<uint8_t, 3>{255, 160, 0}));    // in between
  EXPECT_EQ(pixel(5, 0), (std::array<uint8_t, 3>{0, 0, 255}));      // missed
  EXPECT_EQ(pixel(5, 7), (std::array<uint8_t, 3>{150, 150, 255}));  // never observed
  EXPECT_EQ(pixel(0, 0), (std::array<uint8_t, 3>{255, 255, 255}));  // free
  EXPECT_EQ(pixel(0, 8), (std::array<uint8_t, 3>{205, 205, 205}));  // unknown
}

TEST(CompareMaps, RadiiAndThresholdAreOptions) {
  MapComparisonOptions options;
  options.occupied_min_value = 80;  // (7, 4) at 70 is no longer a hit
  options.match_radius_cells = 0;
  options.phantom_radius_cells = 3;
  const auto result = CompareMaps(HandMap(), WallTruth(), options);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->map_occupied, 4);
  EXPECT_EQ(result->correct, 1);   // only (5, 2)
  EXPECT_EQ(result->phantom, 1);   // only (9, 9); (2, 2) is exactly three cells away
  EXPECT_EQ(result->recalled, 1);  // only (5, 2)
  options.phantom_radius_cells = -1;
  EXPECT_FALSE(CompareMaps(HandMap(), WallTruth(), options).ok());
}

// Truth at 0.1 m: a wall x in [1.0, 1.1), y in [0, 2), in a 3 x 2 m free area.
int8_t WallValue(const Eigen::Vector2d& p) { return p.x() >= 1.0 && p.x() < 1.1 ? 100 : 0; }

TEST(CompareMaps, ResamplesFinerAndCoarserMaps) {
  const OccupancyGrid truth = GridFrom(0.1, 30, 20, Eigen::Vector2d::Zero(), WallValue);
  for (const double res : {0.05, 0.1, 0.2}) {
    const int w = static_cast<int>(std::lround(3.0 / res)),
              h = static_cast<int>(std::lround(2.0 / res));
    const OccupancyGrid map = GridFrom(res, w, h, Eigen::Vector2d::Zero(), [&](const auto& p) {
      // The coarse map marks the whole coarse cell [1.0, 1.2) holding the wall.
      if (res > 0.15) return static_cast<int8_t>(std::abs(p.x() - 1.1) < 0.05 ? 100 : 0);
      return WallValue(p);
    });
    const auto result = CompareMaps(map, truth);
    ASSERT_TRUE(result.ok()) << res;
    EXPECT_DOUBLE_EQ(result->precision, 1.0) << res;
    EXPECT_DOUBLE_EQ(result->recall, 1.0) << res;
    EXPECT_EQ(result->truth_observed, 20) << res;
    EXPECT_EQ(result->map_occupied, res > 0.15 ? 40 : 20) << res;
  }
  // A finer map with a one-cell-thick wall is not lost between target cell centres.
  const OccupancyGrid thin = GridFrom(0.05, 60, 40, Eigen::Vector2d::Zero(), [](const auto& p) {
    return static_cast<int8_t>(p.x() >= 1.05 && p.x() < 1.1 ? 100 : 0);
  });
  const OccupancyGrid on_truth = ResampleOntoGrid(thin, truth);
  EXPECT_EQ(on_truth.at(10, 7), 100);
  EXPECT_EQ(on_truth.at(11, 7), 0);
}

TEST(CompareMaps, MapCellsBeyondTheTruthCountAsPhantoms) {
  const OccupancyGrid truth = GridFrom(0.1, 30, 20, Eigen::Vector2d::Zero(), WallValue);
  // Same lattice, shifted by (-5, -3) cells and larger; one extra wall 1 m left of the truth.
  const OccupancyGrid map = GridFrom(0.1, 40, 30, Eigen::Vector2d(-0.5, -0.3), [](const auto& p) {
    if (p.x() >= 1.0 && p.x() < 1.1 && p.y() > 0.0 && p.y() < 2.0) return int8_t{100};
    if (p.x() >= -0.4 && p.x() < -0.3 && p.y() > 0.0 && p.y() < 1.0) return int8_t{100};
    return int8_t{0};
  });
  const auto result = CompareMaps(map, truth);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->correct, 20);
  EXPECT_EQ(result->phantom, 10);
  EXPECT_EQ(result->map_occupied, 30);
  EXPECT_DOUBLE_EQ(result->recall, 1.0);
}

TEST(CompareMaps, EmptyMapsGiveZerosNotNaN) {
  const OccupancyGrid unknown = OccupancyGrid::Filled(1.0, 4, 4, Eigen::Vector2d::Zero());
  const auto result = CompareMaps(unknown, unknown);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->precision, 0.0);
  EXPECT_EQ(result->recall, 0.0);
  EXPECT_EQ(result->phantom_fraction, 0.0);
  OccupancyGrid broken = unknown;
  broken.cells.resize(3);
  EXPECT_FALSE(CompareMaps(broken, unknown).ok());
  // Far-apart grids would need a gigantic comparison frame: refused.
  OccupancyGrid far = unknown;
  far.origin_m = Eigen::Vector2d(1e7, 1e7);
  EXPECT_FALSE(CompareMaps(far, unknown).ok());
}

}  // namespace
}  // namespace longterm_mapper2d
