#pragma once

#include <cstdint>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/config/option_errors.h"
#include "longterm_mapper2d/core/io/map_image_io.h"
#include "longterm_mapper2d/core/map/occupancy_grid.h"

namespace longterm_mapper2d {

struct MapComparisonOptions {
  // Cells at or above this value are occupied (map_server's occupied_thresh 0.65); any other
  // non-negative value is observed free space.
  int occupied_min_value = 65;
  // A map cell is correct within this many cells (Chebyshev) of a true occupied cell, and a true
  // cell is recalled within this many cells of an occupied map cell.
  int match_radius_cells = 1;
  // A map cell farther than this from every true occupied cell is a phantom.
  int phantom_radius_cells = 2;
  // Refuse comparison frames larger than this.
  int64_t max_cells = 100000000;

  template <class V>
  void Visit(V& v) {
    v("occupied_min_value", occupied_min_value);
    v("match_radius_cells", match_radius_cells);
    v("phantom_radius_cells", phantom_radius_cells);
    v("max_cells", max_cells);
  }
  void Validate(OptionErrors& e) const {
    e.Require(occupied_min_value >= 1 && occupied_min_value <= 100, "occupied_min_value",
              "must be in [1, 100]");
    e.Require(match_radius_cells >= 0, "match_radius_cells", "must be non-negative");
    e.Require(phantom_radius_cells >= match_radius_cells, "phantom_radius_cells",
              "must be at least match_radius_cells");
    e.Require(max_cells > 0, "max_cells", "must be positive");
  }
};

// Occupied-cell agreement of a map with a ground-truth grid of the same (map) frame. Counts are
// cells of the truth's lattice; ratios with an empty denominator are 0.
struct MapComparison {
  int64_t map_occupied = 0;         // occupied map cells (after resampling)
  int64_t correct = 0;              // ... within match_radius_cells of a true occupied cell
  int64_t on_truth = 0;             // ... on a true occupied cell itself (radius 0)
  int64_t phantom = 0;              // ... farther than phantom_radius_cells from all of them
  int64_t truth_occupied = 0;       // true occupied cells
  int64_t truth_observed = 0;       // ... that the map observed (not unknown there)
  int64_t recalled = 0;             // ... observed and within match_radius_cells of a map hit
  double precision = 0.0;           // correct / map_occupied
  double precision_on_truth = 0.0;  // on_truth / map_occupied: the strict figure, no tolerance
  double recall = 0.0;              // recalled / truth_observed
  double phantom_fraction = 0.0;    // phantom / map_occupied
};

// Resamples `source` onto the lattice of `frame` (its resolution, origin and size). Each target
// cell takes the strongest class, occupied > free > unknown, among the source cell under its
// centre and the source cells whose centres fall inside it, so that a finer source does not
// lose thin walls and a coarser one still covers every target cell. Output values are 100, 0
// or -1 (occupied_min_value decides what is occupied).
OccupancyGrid ResampleOntoGrid(const OccupancyGrid& source, const OccupancyGrid& frame,
                               int occupied_min_value = 65);

// Compares `map` with `truth`. Both are in the map frame; the comparison runs on the truth's
// lattice, extended to cover the map, so that map cells outside the truth's extent still count.
// When `diff` is given it receives the comparison image (top row first): correct cells green,
// phantoms red, occupied map cells between the two radii orange, observed true cells that were
// missed blue, unobserved true cells light blue, other observed map cells white, unknown grey.
StatusOr<MapComparison> CompareMaps(const OccupancyGrid& map, const OccupancyGrid& truth,
                                    const MapComparisonOptions& options = {},
                                    RgbImage* diff = nullptr);

}  // namespace longterm_mapper2d
