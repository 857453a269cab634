#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"

namespace longterm_mapper2d {

// A 2D occupancy grid in the map frame, laid out like nav_msgs/OccupancyGrid: cell (ix, iy) covers
// [origin + ix * res, origin + (ix + 1) * res) x [origin + iy * res, origin + (iy + 1) * res), and
// cells are stored row-major starting from the bottom row (iy = 0). Values: kUnknown (-1) or an
// occupancy probability in percent, 0 (free) .. 100 (occupied).
struct OccupancyGrid {
  static constexpr int8_t kUnknown = -1;
  static constexpr int8_t kFree = 0;
  static constexpr int8_t kOccupied = 100;

  double resolution_m = 0.05;
  int width = 0;
  int height = 0;
  // Map coordinates of the lower-left corner of cell (0, 0).
  Eigen::Vector2d origin_m = Eigen::Vector2d::Zero();
  // width * height values, row-major from the bottom row.
  std::vector<int8_t> cells;

  // A grid of the given size with every cell set to `fill`.
  static OccupancyGrid Filled(double resolution_m, int width, int height,
                              const Eigen::Vector2d& origin_m, int8_t fill = kUnknown) {
    OccupancyGrid grid;
    grid.resolution_m = resolution_m;
    grid.width = width;
    grid.height = height;
    grid.origin_m = origin_m;
    grid.cells.assign(static_cast<std::size_t>(width > 0 ? width : 0) *
                          static_cast<std::size_t>(height > 0 ? height : 0),
                      fill);
    return grid;
  }

  bool InBounds(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < width && iy < height; }
  std::size_t Index(int ix, int iy) const {
    return static_cast<std::size_t>(iy) * static_cast<std::size_t>(width) +
           static_cast<std::size_t>(ix);
  }
  int8_t at(int ix, int iy) const { return cells[Index(ix, iy)]; }
  int8_t& at(int ix, int iy) { return cells[Index(ix, iy)]; }

  // The cell containing a point of the map frame (it may lie outside the grid: check InBounds).
  Eigen::Vector2i WorldToCell(const Eigen::Vector2d& p_map) const {
    return {static_cast<int>(std::floor((p_map.x() - origin_m.x()) / resolution_m)),
            static_cast<int>(std::floor((p_map.y() - origin_m.y()) / resolution_m))};
  }
  // Map coordinates of the centre of cell (ix, iy).
  Eigen::Vector2d CellCenter(int ix, int iy) const {
    return origin_m + resolution_m * Eigen::Vector2d(ix + 0.5, iy + 0.5);
  }
  // Map coordinates of the upper-right corner of the grid.
  Eigen::Vector2d MaxCorner() const {
    return origin_m + resolution_m * Eigen::Vector2d(width, height);
  }

  // Checks that the fields describe a usable grid: positive finite resolution, finite origin,
  // non-negative size matching the cell count, values in {-1} U [0, 100].
  Status Validate() const {
    if (!(resolution_m > 0.0) || !std::isfinite(resolution_m)) {
      return Status::Error("grid resolution must be positive and finite");
    }
    if (!origin_m.allFinite()) return Status::Error("grid origin is not finite");
    if (width < 0 || height < 0) return Status::Error("grid size is negative");
    if (cells.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {
      return Status::Error("grid has " + std::to_string(cells.size()) + " cells, expected " +
                           std::to_string(width) + " x " + std::to_string(height));
    }
    for (const int8_t v : cells) {
      if (v < kUnknown || v > kOccupied) {
        return Status::Error("grid cell value " + std::to_string(v) + " outside [-1, 100]");
      }
    }
    return Status::Ok();
  }
};

}  // namespace longterm_mapper2d
