#pragma once

#include <cstdint>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/map/grid_options.h"
#include "longterm_mapper2d/core/map/occupancy_grid.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d {

struct GridRenderStats {
  int scans_used = 0;
  int scans_skipped = 0;  // bad geometry or non-finite pose
  int64_t beams_cast = 0;
};

// Renders the scans into a grid in their common frame (the map frame of PosedScan::map_T_laser).
// Bounds are computed first from the sensor positions and the capped beam endpoints (plus
// margin_m), then every beam is traced with integer Bresenham steps. Within one scan a cell is
// updated at most once, and hits are applied first, so neighbouring beams of the same scan do not
// erase a return at grazing incidence. NaN readings and readings below range_min are ignored.
// Scans with bad geometry or non-finite poses are skipped (counted in `stats`); an error is
// returned for invalid options, when no scan is usable, or when the grid would exceed max_cells.
StatusOr<OccupancyGrid> RenderOccupancyGrid(const std::vector<PosedScan>& scans,
                                            const GridOptions& options,
                                            GridRenderStats* stats = nullptr);

}  // namespace longterm_mapper2d
