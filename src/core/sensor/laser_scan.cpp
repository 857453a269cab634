#include "longterm_mapper2d/core/sensor/laser_scan.h"

#include <algorithm>

#include <cmath>

namespace longterm_mapper2d {

bool LaserScan::IsValidRange(float range_m) const {
  return std::isfinite(range_m) && range_m >= range_min_m && range_m < range_max_m;
}

Status LaserScan::ValidateGeometry() const {
  if (ranges.empty()) return Status::Error("scan has no beams");
  if (!std::isfinite(angle_min_rad) || !std::isfinite(angle_increment_rad)) {
    return Status::Error("scan angles are not finite");
  }
  if (!(angle_increment_rad > 0.0)) {
    return Status::Error("scan angle_increment must be positive, got " +
                         std::to_string(angle_increment_rad));
  }
  if (FieldOfView() > 2.0 * M_PI + 1e-6) {
    return Status::Error("scan field of view exceeds 2*pi (" + std::to_string(ranges.size()) +
                         " beams x " + std::to_string(angle_increment_rad) + " rad)");
  }
  if (!std::isfinite(range_min_m) || !std::isfinite(range_max_m) || range_min_m < 0.0 ||
      !(range_max_m > range_min_m)) {
    return Status::Error("scan range interval is invalid: [" + std::to_string(range_min_m) + ", " +
                         std::to_string(range_max_m) + ")");
  }
  if (!std::isfinite(stamp_s)) return Status::Error("scan stamp is not finite");
  return Status::Ok();
}

void LaserScan::MakeCounterClockwise() {
  if (!(angle_increment_rad < 0.0) || ranges.empty()) return;
  angle_min_rad += angle_increment_rad * static_cast<double>(ranges.size() - 1);
  angle_increment_rad = -angle_increment_rad;
  std::reverse(ranges.begin(), ranges.end());
}

}  // namespace longterm_mapper2d
