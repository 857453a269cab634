#include "longterm_mapper2d/core/sensor/odometry_buffer.h"

#include <algorithm>
#include <cmath>

namespace longterm_mapper2d {

Status OdometryBuffer::Add(double stamp_s, const Pose2& odom_T_base) {
  if (!std::isfinite(stamp_s) || !odom_T_base.IsFinite()) {
    return Status::Error("odometry sample is not finite");
  }
  if (!samples_.empty()) {
    const double last = samples_.back().stamp_s;
    if (stamp_s < last) {
      return Status::Error("odometry went back in time: " + std::to_string(stamp_s) + " < " +
                           std::to_string(last));
    }
    if (stamp_s == last) {
      samples_.back().pose = odom_T_base;
      return Status::Ok();
    }
  }
  samples_.push_back({stamp_s, odom_T_base});
  return Status::Ok();
}

std::optional<Pose2> OdometryBuffer::Interpolate(double stamp_s, double tolerance_s) const {
  if (samples_.empty() || !std::isfinite(stamp_s)) return std::nullopt;
  if (stamp_s <= samples_.front().stamp_s) {
    if (samples_.front().stamp_s - stamp_s <= tolerance_s) return samples_.front().pose;
    return std::nullopt;
  }
  if (stamp_s >= samples_.back().stamp_s) {
    if (stamp_s - samples_.back().stamp_s <= tolerance_s) return samples_.back().pose;
    return std::nullopt;
  }
  const auto after = std::lower_bound(
      samples_.begin(), samples_.end(), stamp_s,
      [](const StampedPose2& sample, double t) { return sample.stamp_s < t; });
  const auto before = after - 1;
  if (after->stamp_s == stamp_s) return after->pose;
  const double t = (stamp_s - before->stamp_s) / (after->stamp_s - before->stamp_s);
  return longterm_mapper2d::Interpolate(before->pose, after->pose, t);
}

void OdometryBuffer::TrimBefore(double stamp_s) {
  const auto first_after = std::lower_bound(
      samples_.begin(), samples_.end(), stamp_s,
      [](const StampedPose2& sample, double t) { return sample.stamp_s < t; });
  if (first_after - samples_.begin() > 1) samples_.erase(samples_.begin(), first_after - 1);
}

}  // namespace longterm_mapper2d
