#pragma once

#include <cstdint>

#include "longterm_mapper2d/core/config/option_errors.h"

namespace longterm_mapper2d {

// How raw scans are rendered into an occupancy grid (log-odds ray casting).
struct GridOptions {
  double resolution_m = 0.05;
  // Returns farther than this are treated like no-return beams (long readings are unreliable).
  double max_range_m = 30.0;
  // No-return beams (inf, >= the scan's range_max, or beyond max_range_m) clear free space up to
  // this distance: the beam went at least that far. 0 disables it.
  double free_space_max_range_m = 10.0;
  // Log-odds increments: log(p / (1 - p)) of the hit and miss probabilities (0.7 and 0.35).
  double log_odds_hit = 0.85;
  double log_odds_miss = -0.6;
  // Clamping keeps cells able to change when the world changes.
  double log_odds_min = -2.0;
  double log_odds_max = 3.5;
  // Observed cells with probability >= occupied_threshold are written 100, <= free_threshold 0,
  // others round(100 p); cells never crossed by a beam are -1.
  double occupied_threshold = 0.6;
  double free_threshold = 0.4;
  // Border of unknown cells around everything the beams reached.
  double margin_m = 0.5;
  // Refuse grids larger than this (a wild pose would otherwise allocate gigabytes).
  int64_t max_cells = 100000000;

  template <class V>
  void Visit(V& v) {
    v("resolution_m", resolution_m);
    v("max_range_m", max_range_m);
    v("free_space_max_range_m", free_space_max_range_m);
    v("log_odds_hit", log_odds_hit);
    v("log_odds_miss", log_odds_miss);
    v("log_odds_min", log_odds_min);
    v("log_odds_max", log_odds_max);
    v("occupied_threshold", occupied_threshold);
    v("free_threshold", free_threshold);
    v("margin_m", margin_m);
    v("max_cells", max_cells);
  }
  void Validate(OptionErrors& e) const {
    e.Require(resolution_m > 0.0 && resolution_m <= 10.0, "resolution_m", "must be in (0, 10]");
    e.Require(max_range_m > 0.0, "max_range_m", "must be positive");
    e.Require(free_space_max_range_m >= 0.0, "free_space_max_range_m", "must be non-negative");
    e.Require(log_odds_hit > 0.0, "log_odds_hit", "must be positive");
    e.Require(log_odds_miss < 0.0, "log_odds_miss", "must be negative");
    e.Require(log_odds_min < 0.0, "log_odds_min", "must be negative");
    e.Require(log_odds_max > 0.0, "log_odds_max", "must be positive");
    e.Require(free_threshold > 0.0 && free_threshold < occupied_threshold, "free_threshold",
              "must be in (0, occupied_threshold)");
    e.Require(occupied_threshold < 1.0, "occupied_threshold", "must be below 1");
    e.Require(margin_m >= 0.0, "margin_m", "must be non-negative");
    e.Require(max_cells > 0, "max_cells", "must be positive");
  }
};

}  // namespace longterm_mapper2d
