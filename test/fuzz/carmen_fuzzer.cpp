// Fuzzes ParseCarmenLog (CARMEN .clf/.log text). Malformed input must give an error, never a crash
// or UB. A log that parses goes straight to the mapper, so every scan must have readings, a finite
// stamp and finite odometry and laser-mount poses (one NaN pose silently poisons the whole map),
// and the scans must come in time order.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "longterm_mapper2d/core/io/carmen_reader.h"

namespace longterm_mapper2d {
namespace {

void Check(bool condition) {
  if (!condition) __builtin_trap();
}

void FuzzOne(const std::string& text) {
  const StatusOr<CarmenLog> log = ParseCarmenLog(text, "fuzz.clf");
  if (!log.ok()) {
    Check(!log.status().message().empty());
    return;
  }
  double previous_stamp = -INFINITY;
  for (const ScanInput& input : log->scans) {
    Check(!input.scan.ranges.empty());
    Check(std::isfinite(input.scan.stamp_s));
    Check(input.scan.stamp_s >= previous_stamp);
    previous_stamp = input.scan.stamp_s;
    Check(input.odom_T_base.IsFinite());
    Check(input.base_T_laser.IsFinite());
  }
  Check(log->no_return_range_m >= 0.0);
}

}  // namespace
}  // namespace longterm_mapper2d

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  longterm_mapper2d::FuzzOne(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
