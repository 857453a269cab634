#include "longterm_mapper2d/core/map/occupancy_grid.h"

#include <gtest/gtest.h>

namespace longterm_mapper2d {
namespace {

// A 4 x 3 grid with every kind of value at distinct places.
OccupancyGrid MakeGrid() {
  OccupancyGrid grid = OccupancyGrid::Filled(0.1, 4, 3, Eigen::Vector2d(-1.25, 2.5));
  grid.at(0, 0) = 100;
  grid.at(1, 0) = 0;
  grid.at(3, 2) = 100;
  grid.at(2, 1) = 0;
  grid.at(1, 2) = 0;
  return grid;
}

TEST(OccupancyGrid, CellAndWorldIndicesAgree) {
  const OccupancyGrid grid = MakeGrid();
  EXPECT_EQ(grid.WorldToCell(Eigen::Vector2d(-1.25, 2.5)), Eigen::Vector2i(0, 0));
  EXPECT_EQ(grid.WorldToCell(Eigen::Vector2d(-1.26, 2.5)), Eigen::Vector2i(-1, 0));
  EXPECT_EQ(grid.WorldToCell(Eigen::Vector2d(-0.96, 2.71)), Eigen::Vector2i(2, 2));
  EXPECT_TRUE(grid.CellCenter(2, 1).isApprox(Eigen::Vector2d(-1.0, 2.65)));
  EXPECT_EQ(grid.WorldToCell(grid.CellCenter(3, 2)), Eigen::Vector2i(3, 2));
  EXPECT_EQ(grid.Index(1, 2), 9u);
  EXPECT_TRUE(grid.InBounds(3, 2));
  EXPECT_FALSE(grid.InBounds(4, 0));
  EXPECT_TRUE(grid.Validate().ok());
  OccupancyGrid bad = grid;
  bad.cells.pop_back();
  EXPECT_FALSE(bad.Validate().ok());
}

}  // namespace
}  // namespace longterm_mapper2d
