#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "longterm_mapper2d/core/common/stage_timer.h"

namespace longterm_mapper2d {

// What the mapper did with its input, for --stats, ~status and the benchmarks.
struct MapperStats {
  std::uint64_t scans_received = 0;
  std::uint64_t scans_processed = 0;
  // Skipped scans by reason ("no_motion", "too_few_beams", "invalid_geometry", ...).
  std::map<std::string, std::uint64_t> scans_skipped;
  // Other named counters ("tracker_failures", "ranges_cleaned", ...).
  std::map<std::string, std::uint64_t> counters;
  StageTimes stage_times;

  std::uint64_t TotalSkipped() const {
    std::uint64_t total = 0;
    for (const auto& [reason, count] : scans_skipped) total += count;
    return total;
  }
};

}  // namespace longterm_mapper2d
