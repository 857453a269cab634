#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d {

struct CarmenReaderOptions {
  // Readings at or above the log's no-return value are not returns. 0 = detect it: the largest
  // reading of the log, when it occurs at least `min_no_return_count` times (a saturated value,
  // such as 81.83 in intel, 81.91 in fr079 or 50.0 in aces).
  double no_return_range_m = 0.0;
  int min_no_return_count = 10;
  // A detected no-return value must be at least this far (a room of 5 m walls is not saturation).
  double min_detected_no_return_m = 20.0;
  // Readings above this are never used, whatever the log says.
  double max_range_m = 80.0;
  // Extrapolation allowed when an ODOM record does not bracket a scan stamp.
  double odometry_tolerance_s = 0.5;
};

struct CarmenLog {
  // Scans in time order, each with odom_T_base interpolated from the ODOM records at the scan's
  // ipc timestamp (the scan line's own odometry pose where ODOM records do not cover it) and the
  // base->laser offset from the line's laser and robot pose fields.
  std::vector<ScanInput> scans;
  std::vector<StampedPose2> odometry;
  double no_return_range_m = 0.0;  // the value used (0 if the log has none)
  std::uint64_t readings_no_return = 0;
  std::uint64_t scans_with_line_odometry = 0;  // scans placed by their own pose fields
  // False when the ODOM records are placeholders (no motion, or no advancing stamps).
  bool odom_records_used = false;
  // False when the laser and robot pose fields disagree from line to line (a corrected log):
  // the offset is then taken as identity.
  bool laser_offset_from_log = true;
  std::map<std::string, std::uint64_t> skipped_messages;  // message type -> count
};

// Reads FLASER, ROBOTLASER1 and ODOM records of a CARMEN log. Comments ('#') and other message
// types are skipped (and counted). A malformed record is an error naming the file and line.
//
// Beam geometry: old FLASER lines carry no angles; they start at -pi/2 with a step of pi/180 for
// 180/181 beams and pi/360 for 360/361 beams (pi/(n-1) otherwise, a 180-degree field of view).
// ROBOTLASER1 lines carry start angle and angular resolution.
StatusOr<CarmenLog> ReadCarmenLog(const std::string& path, const CarmenReaderOptions& options = {});
StatusOr<CarmenLog> ParseCarmenLog(const std::string& text, const std::string& source_name,
                                   const CarmenReaderOptions& options = {});

}  // namespace longterm_mapper2d
