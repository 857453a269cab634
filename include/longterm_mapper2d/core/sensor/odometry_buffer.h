#pragma once

#include <optional>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/geometry/pose2.h"

namespace longterm_mapper2d {

// Odometry samples (odom_T_base) in time order, interpolated at scan stamps. The CARMEN path, the
// bag path and the node all place scans through this class, so they place them alike.
class OdometryBuffer {
 public:
  // A sample older than the newest one is refused (the caller decides whether that is a reset);
  // a sample with the newest stamp replaces it.
  Status Add(double stamp_s, const Pose2& odom_T_base);

  // Linear in translation, shortest arc in angle. Outside the covered interval the nearest
  // sample is used if it is within `tolerance_s`; otherwise there is no pose.
  std::optional<Pose2> Interpolate(double stamp_s, double tolerance_s = 0.0) const;

  bool empty() const { return samples_.empty(); }
  std::size_t size() const { return samples_.size(); }
  double front_stamp_s() const { return samples_.front().stamp_s; }
  double back_stamp_s() const { return samples_.back().stamp_s; }
  // Drops samples older than stamp_s, keeping one before it so that it can still be interpolated.
  void TrimBefore(double stamp_s);
  void Clear() { samples_.clear(); }

 private:
  std::vector<StampedPose2> samples_;
};

}  // namespace longterm_mapper2d
