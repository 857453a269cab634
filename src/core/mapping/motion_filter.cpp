#include "longterm_mapper2d/core/mapping/motion_filter.h"

#include <algorithm>
#include <cmath>

#include "longterm_mapper2d/core/geometry/fast_atan2.h"

namespace longterm_mapper2d {
namespace {

// Per-point evidence, before it is pooled per object.
constexpr char kStill = 0;
constexpr char kMovedIn = 1;   // stands where the earlier scan saw free space
constexpr char kRevealed = 2;  // was hidden behind something that has left since

}  // namespace

const MotionFilter::Reference* MotionFilter::ReferenceFor(double stamp_s) {
  // Time going backwards (a looped bag, a reset clock) makes the history meaningless.
  if (!history_.empty() && history_.back().stamp_s > stamp_s) history_.clear();
  while (!history_.empty() && history_.front().stamp_s < stamp_s - options_.max_age_s) {
    history_.pop_front();
  }
  // The oldest one left: the longest baseline odometry can still be trusted over.
  if (history_.empty() || history_.front().stamp_s > stamp_s - options_.min_baseline_s) {
    return nullptr;
  }
  return &history_.front();
}

double MotionFilter::FreeRange(const LaserScan& scan, const ProjectorGeometry& geometry,
                               double bearing_rad, double window_rad) const {
  const int centre = geometry.BinOf(bearing_rad);
  if (centre < 0) return 0.0;
  const int half_window = static_cast<int>(std::ceil(window_rad / geometry.angle_increment_rad));
  double free_m = options_.no_return_free_m;
  for (int offset = -half_window; offset <= half_window; ++offset) {
    const int beam = geometry.Shift(centre, offset);
    if (beam < 0) return 0.0;  // the window leaves the field of view: not all of it was seen
    const float r = scan.ranges[beam];
    if (std::isnan(r) || (std::isfinite(r) && r < scan.range_min_m)) return 0.0;  // no reading
    if (std::isfinite(r) && r < scan.range_max_m) free_m = std::min(free_m, static_cast<double>(r));
  }
  return free_m;
}

int MotionFilter::FindMoving(const ScanInput& input, const Cloud& base_points,
                             std::vector<char>* moving) {
  moving->assign(base_points.size(), kStill);
  if (!options_.enabled) return 0;
  const Reference* reference = ReferenceFor(input.scan.stamp_s);
  if (reference == nullptr) return 0;
  const LaserScan& earlier = reference->scan;
  const Pose2 earlier_T_base = reference->odom_T_laser.inverse() * input.odom_T_base;
  const Pose2 laser_T_earlier =
      (input.odom_T_base * input.base_T_laser).inverse() * reference->odom_T_laser;
  const ProjectorGeometry geometry = ProjectorGeometry::FromScan(input.scan, 1e9);
  // Odometry's error grows with the motion between the two scans: so do the margins.
  const double travel_m = laser_T_earlier.translation().norm();
  const double turn_rad = std::abs(laser_T_earlier.theta());
  const double window_rad = options_.window_rad + options_.odometry_error_per_rad * turn_rad;
  auto margin = [&](double range_m) {
    return options_.min_distance_m + options_.odometry_error_per_m * travel_m +
           (options_.distance_per_m + options_.odometry_error_per_rad * turn_rad) * range_m;
  };
  for (std::size_t i = 0; i < base_points.size(); ++i) {
    const Eigen::Vector2d q = earlier_T_base * base_points[i].point_m;
    const double range_m = q.norm();
    const double bearing_rad = FastAtan2(q.y(), q.x());
    if (FreeRange(earlier, reference->geometry, bearing_rad, window_rad) >
        range_m + margin(range_m)) {
      (*moving)[i] = kMovedIn;
      continue;
    }
    // Hidden then? What hid it, if the beam now passes where it stood, has moved on: a person
    // walking away shows its back where its front was hidden before.
    const int beam = reference->geometry.BinOf(bearing_rad);
    if (beam < 0 || !earlier.IsValidRange(earlier.ranges[beam])) continue;
    const double hidden_by_m = earlier.ranges[beam];
    if (hidden_by_m >= range_m - margin(range_m)) continue;
    const double angle = earlier.BeamAngle(beam);
    const Eigen::Vector2d occluder =
        laser_T_earlier *
        Eigen::Vector2d(hidden_by_m * std::cos(angle), hidden_by_m * std::sin(angle));
    const double occluder_range_m = occluder.norm();
    if (FreeRange(input.scan, geometry, FastAtan2(occluder.y(), occluder.x()), window_rad) >
        occluder_range_m + margin(occluder_range_m)) {
      (*moving)[i] = kRevealed;
    }
  }
  // Judged on the points' own evidence: pooled per object, a misplaced wall would not count.
  const auto evidence = moving->size() - std::count(moving->begin(), moving->end(), kStill);
  if (evidence > options_.max_moving_fraction * static_cast<double>(base_points.size())) {
    std::fill(moving->begin(), moving->end(), kStill);
    return 0;
  }
  return MarkObjects(base_points, moving);
}

int MotionFilter::MarkObjects(const Cloud& base_points, std::vector<char>* moving) const {
  // Scan points are in beam order: an object is a run of points each within max_gap_m of the
  // previous one. A small object moves as a whole if most of its points say so; a single point
  // proves nothing (a chair leg slips between the beams of one scan and not of the next), and a
  // large object (a wall) is left to the merger.
  const double max_gap_sq = options_.max_gap_m * options_.max_gap_m;
  const std::size_t n = base_points.size();
  std::vector<char>& m = *moving;
  int count = 0;
  for (std::size_t begin = 0; begin < n;) {
    std::size_t end = begin + 1;
    while (end < n &&
           (base_points[end].point_m - base_points[end - 1].point_m).squaredNorm() <= max_gap_sq) {
      ++end;
    }
    const auto first = m.begin() + begin, last = m.begin() + end;
    const bool small =
        (base_points[end - 1].point_m - base_points[begin].point_m).norm() <= options_.max_object_m;
    const long size = static_cast<long>(end - begin);
    const long evidence = size - std::count(first, last, kStill);
    if (small && size >= options_.min_object_points && 2 * evidence >= size) {
      std::fill(first, last, kMovedIn);
      count += static_cast<int>(size);
    } else {
      std::fill(first, last, kStill);
    }
    begin = end;
  }
  return count;
}

void MotionFilter::Remember(const ScanInput& input) {
  if (!options_.enabled) return;
  if (!history_.empty() && history_.back().stamp_s > input.scan.stamp_s) history_.clear();
  Reference reference{input.scan.stamp_s, input.odom_T_base * input.base_T_laser, input.scan,
                      ProjectorGeometry::FromScan(input.scan, 1e9)};
  history_.push_back(std::move(reference));
}

}  // namespace longterm_mapper2d
