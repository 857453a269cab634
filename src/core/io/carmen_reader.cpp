#include "longterm_mapper2d/core/io/carmen_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "longterm_mapper2d/core/io/atomic_file.h"
#include "longterm_mapper2d/core/sensor/odometry_buffer.h"

namespace longterm_mapper2d {
namespace {

// Splits one line into whitespace-separated tokens without allocating per token.
class Tokens {
 public:
  explicit Tokens(const char* begin, const char* end) : pos_(begin), end_(end) {}
  bool Next(const char*& token, std::size_t& length) {
    while (pos_ < end_ && (*pos_ == ' ' || *pos_ == '\t' || *pos_ == '\r')) ++pos_;
    if (pos_ >= end_) return false;
    token = pos_;
    while (pos_ < end_ && *pos_ != ' ' && *pos_ != '\t' && *pos_ != '\r') ++pos_;
    length = static_cast<std::size_t>(pos_ - token);
    return true;
  }
  bool NextDouble(double& value) {
    const char* token;
    std::size_t length;
    if (!Next(token, length)) return false;
    char buffer[64];
    if (length >= sizeof(buffer)) return false;
    std::copy(token, token + length, buffer);
    buffer[length] = '\0';
    char* parsed_end = nullptr;
    value = std::strtod(buffer, &parsed_end);
    return parsed_end == buffer + length;
  }
  // Poses and stamps: "nan", "inf" and overflowing numbers (1e400) are malformed.
  bool NextFinite(double& value) { return NextDouble(value) && std::isfinite(value); }
  bool NextInt(long& value) {
    double d;
    if (!NextDouble(d) || d != std::floor(d) || std::abs(d) > 1e9) return false;
    value = static_cast<long>(d);
    return true;
  }

 private:
  const char* pos_;
  const char* end_;
};

struct RawScan {
  ScanInput input;
  Pose2 line_odom_T_base;
  int line_number = 0;
};

double FlaserIncrement(long beams) {
  if (beams == 180 || beams == 181) return M_PI / 180.0;
  if (beams == 360 || beams == 361) return M_PI / 360.0;
  return M_PI / static_cast<double>(std::max<long>(beams - 1, 1));
}

}  // namespace

StatusOr<CarmenLog> ParseCarmenLog(const std::string& text, const std::string& source_name,
                                   const CarmenReaderOptions& options) {
  CarmenLog log;
  std::vector<RawScan> raw_scans;
  OdometryBuffer odometry;
  std::vector<StampedPose2> odometry_records;
  int line_number = 0;
  const char* cursor = text.data();
  const char* const text_end = text.data() + text.size();
  auto error = [&](const std::string& what) {
    return Status::Error(source_name + ":" + std::to_string(line_number) + ": " + what);
  };

  while (cursor < text_end) {
    const char* line_end = std::find(cursor, text_end, '\n');
    ++line_number;
    Tokens tokens(cursor, line_end);
    cursor = line_end + 1;
    const char* tag;
    std::size_t tag_length;
    if (!tokens.Next(tag, tag_length) || tag[0] == '#') continue;
    const std::string type(tag, tag_length);

    if (type == "ODOM") {
      // ODOM x y theta tv rv accel timestamp hostname logger_timestamp
      double x, y, theta, tv, rv, accel, stamp;
      if (!tokens.NextFinite(x) || !tokens.NextFinite(y) || !tokens.NextFinite(theta) ||
          !tokens.NextDouble(tv) || !tokens.NextDouble(rv) || !tokens.NextDouble(accel) ||
          !tokens.NextFinite(stamp)) {
        return error("malformed ODOM record (expected x y theta tv rv accel timestamp ...)");
      }
      odometry_records.push_back({stamp, Pose2(x, y, theta)});
      continue;
    }

    RawScan raw;
    raw.line_number = line_number;
    LaserScan& scan = raw.input.scan;
    long beams = 0;
    if (type == "FLASER" || type == "RLASER") {
      // FLASER n r1..rn x y theta odom_x odom_y odom_theta timestamp hostname logger_timestamp
      if (!tokens.NextInt(beams) || beams <= 0 || beams > 100000) {
        return error("malformed " + type + " record: bad number of readings");
      }
      scan.angle_increment_rad = FlaserIncrement(beams);
      scan.angle_min_rad = -M_PI / 2.0;
      if (type == "RLASER") scan.angle_min_rad += M_PI;  // the rear laser looks backwards
      scan.range_max_m = options.max_range_m;
    } else if (type == "ROBOTLASER1") {
      // ROBOTLASER1 laser_type start_angle fov resolution max_range accuracy remission_mode
      //   n r1..rn n_remissions rem.. laser_x laser_y laser_theta robot_x robot_y robot_theta
      //   tv rv forward_safety side_safety turn_axis timestamp hostname logger_timestamp
      double laser_type, start_angle, fov, resolution, max_range, accuracy, remission_mode;
      if (!tokens.NextDouble(laser_type) || !tokens.NextDouble(start_angle) ||
          !tokens.NextDouble(fov) || !tokens.NextDouble(resolution) ||
          !tokens.NextDouble(max_range) || !tokens.NextDouble(accuracy) ||
          !tokens.NextDouble(remission_mode) || !tokens.NextInt(beams) || beams <= 0 ||
          beams > 100000) {
        return error("malformed ROBOTLASER1 header fields");
      }
      scan.angle_min_rad = start_angle;
      scan.angle_increment_rad = beams > 1 ? fov / static_cast<double>(beams - 1) : resolution;
      if (!(scan.angle_increment_rad > 0.0)) scan.angle_increment_rad = resolution;
      scan.range_max_m = max_range > 0.0 ? std::min(max_range, options.max_range_m)
                                         : options.max_range_m;
    } else {
      ++log.skipped_messages[type];
      continue;
    }

    scan.ranges.resize(static_cast<std::size_t>(beams));
    for (long i = 0; i < beams; ++i) {
      double range;
      if (!tokens.NextDouble(range)) {
        return error(type + " record has fewer than the " + std::to_string(beams) +
                     " readings it announces");
      }
      scan.ranges[static_cast<std::size_t>(i)] = static_cast<float>(range);
    }
    if (type == "ROBOTLASER1") {
      long remissions = 0;
      if (!tokens.NextInt(remissions) || remissions < 0 || remissions > 100000) {
        return error("malformed ROBOTLASER1 remission count");
      }
      for (long i = 0; i < remissions; ++i) {
        double ignored;
        if (!tokens.NextDouble(ignored)) return error("ROBOTLASER1 record lacks remissions");
      }
    }
    double lx, ly, lt, ox, oy, ot;
    if (!tokens.NextFinite(lx) || !tokens.NextFinite(ly) || !tokens.NextFinite(lt) ||
        !tokens.NextFinite(ox) || !tokens.NextFinite(oy) || !tokens.NextFinite(ot)) {
      return error(type + " record lacks finite laser and robot poses");
    }
    if (type == "ROBOTLASER1") {
      double ignored;
      for (int i = 0; i < 5; ++i) {
        if (!tokens.NextDouble(ignored)) return error("ROBOTLASER1 record lacks velocity fields");
      }
    }
    double stamp;
    if (!tokens.NextFinite(stamp)) return error(type + " record lacks a finite timestamp");
    scan.stamp_s = stamp;
    scan.frame_id = type == "RLASER" ? "rear_laser" : "laser";
    scan.range_min_m = 0.0;
    // The laser pose and the robot pose of one line are given in the same frame, so their
    // difference is where the laser sits on the robot.
    const Pose2 laser_pose(lx, ly, lt), robot_pose(ox, oy, ot);
    raw.input.base_T_laser = robot_pose.Between(laser_pose);
    if (!raw.input.base_T_laser.IsFinite()) {
      return error(type + " record: laser and robot poses too large");
    }
    raw.line_odom_T_base = robot_pose;
    raw_scans.push_back(std::move(raw));
  }

  // Records may be out of time order in original logs; the mapper needs them sorted.
  std::stable_sort(odometry_records.begin(), odometry_records.end(),
                   [](const StampedPose2& a, const StampedPose2& b) { return a.stamp_s < b.stamp_s; });
  std::stable_sort(raw_scans.begin(), raw_scans.end(), [](const RawScan& a, const RawScan& b) {
    return a.input.scan.stamp_s < b.input.scan.stamp_s;
  });
  // ODOM records are trusted only if they move and their stamps advance and are distinct; some
  // logs carry placeholder records (all zeros) or stamps printed with too few digits to tell
  // apart, and then each scan line's own odometry pose is used instead.
  bool odometry_usable = odometry_records.size() >= 2 &&
                         odometry_records.back().stamp_s > odometry_records.front().stamp_s;
  if (odometry_usable) {
    // Stamps printed with too few digits repeat: interpolating them would freeze the robot.
    std::size_t repeated = 0;
    for (std::size_t i = 1; i < odometry_records.size(); ++i) {
      repeated += odometry_records[i].stamp_s == odometry_records[i - 1].stamp_s;
    }
    odometry_usable = repeated * 10 < odometry_records.size();
    // The same holds for the scans' own stamps: ODOM is interpolated at them.
    std::size_t scans_repeated = 0;
    for (std::size_t i = 1; i < raw_scans.size(); ++i) {
      scans_repeated += raw_scans[i].input.scan.stamp_s == raw_scans[i - 1].input.scan.stamp_s;
    }
    odometry_usable &= scans_repeated * 10 < raw_scans.size();
  }
  if (odometry_usable) {
    bool moves = false;
    for (const auto& record : odometry_records) {
      moves |= (record.pose.vector() - odometry_records.front().pose.vector()).norm() > 1e-9;
    }
    odometry_usable = moves;
  }
  log.odom_records_used = odometry_usable;
  if (odometry_usable) {
    for (const auto& record : odometry_records) odometry.Add(record.stamp_s, record.pose);
  }
  log.odometry = std::move(odometry_records);

  // The no-return value: a saturated maximum reading.
  double no_return = options.no_return_range_m;
  if (no_return <= 0.0) {
    float max_reading = 0.0f;
    for (const auto& raw : raw_scans) {
      for (float r : raw.input.scan.ranges) max_reading = std::max(max_reading, r);
    }
    std::uint64_t count = 0;
    for (const auto& raw : raw_scans) {
      for (float r : raw.input.scan.ranges) count += (r == max_reading);
    }
    if (max_reading >= options.min_detected_no_return_m &&
        count >= static_cast<std::uint64_t>(options.min_no_return_count)) {
      no_return = max_reading;
    }
  }
  log.no_return_range_m = no_return;

  // A rigid mount gives the same offset on every line. Corrected logs (laser pose from SLAM,
  // robot pose from odometry) do not; their difference is drift, not a mount, so use none.
  bool rigid_offset = true;
  for (const auto& raw : raw_scans) {
    const Pose2 diff = raw_scans.front().input.base_T_laser.Between(raw.input.base_T_laser);
    if (diff.translation().norm() > 0.05 || std::abs(diff.theta()) > 0.05) {
      rigid_offset = false;
      break;
    }
  }
  log.laser_offset_from_log = rigid_offset;
  if (!rigid_offset) {
    for (auto& raw : raw_scans) raw.input.base_T_laser = Pose2();
  }

  log.scans.reserve(raw_scans.size());
  for (auto& raw : raw_scans) {
    LaserScan& scan = raw.input.scan;
    if (no_return > 0.0) {
      scan.range_max_m = std::min(scan.range_max_m, no_return - 1e-3);
      for (float& r : scan.ranges) {
        if (r >= no_return - 1e-3) {
          r = std::numeric_limits<float>::infinity();
          ++log.readings_no_return;
        }
      }
    }
    const auto interpolated = odometry.Interpolate(scan.stamp_s, options.odometry_tolerance_s);
    if (interpolated && !interpolated->IsFinite()) {
      line_number = raw.line_number;
      return error("odometry interpolated at the scan stamp is not finite");
    }
    if (interpolated) {
      raw.input.odom_T_base = *interpolated;
    } else {
      raw.input.odom_T_base = raw.line_odom_T_base;
      ++log.scans_with_line_odometry;
    }
    log.scans.push_back(std::move(raw.input));
  }
  return log;
}

StatusOr<CarmenLog> ReadCarmenLog(const std::string& path, const CarmenReaderOptions& options) {
  auto bytes = ReadFileBytes(path);
  if (!bytes.ok()) return bytes.status();
  return ParseCarmenLog(*bytes, path, options);
}

}  // namespace longterm_mapper2d
