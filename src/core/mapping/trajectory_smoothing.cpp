#include "longterm_mapper2d/core/mapping/trajectory_smoothing.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace longterm_mapper2d {

std::vector<Pose2> SmoothAcrossLocalMaps(const std::vector<double>& stamps_s,
                                         const std::vector<Pose2>& map_T_base,
                                         const std::vector<Pose2>& tracker_T_base,
                                         double half_window_s) {
  const std::size_t n = map_T_base.size();
  if (half_window_s <= 0.0 || n < 2) return map_T_base;
  // Corrections C_j (map_T_tracker as scan j's node has it). C_j * T_i has the position
  // t_j + R_j t_i and the heading th_j + th_i, so the window needs only the sums of t_j, cos th_j
  // and sin th_j: the mean position is mean(t_j) + mean(R_j) t_i, mean(R_j) the mean of the
  // rotation matrices; the heading is th_i plus the direction of (sum cos, sum sin). Sums are
  // taken relative to the first correction (small numbers, no cancellation far from the origin).
  const Pose2 reference = map_T_base[0] * tracker_T_base[0].inverse();
  struct Sums {
    double x = 0.0, y = 0.0, c = 0.0, s = 0.0;
  };
  std::vector<Pose2> corrections(n);
  for (std::size_t j = 0; j < n; ++j) {
    corrections[j] = reference.inverse() * (map_T_base[j] * tracker_T_base[j].inverse());
  }
  Sums sums;
  auto add = [&](std::size_t j, double sign) {
    sums.x += sign * corrections[j].x();
    sums.y += sign * corrections[j].y();
    sums.c += sign * std::cos(corrections[j].theta());
    sums.s += sign * std::sin(corrections[j].theta());
  };
  std::vector<Pose2> smoothed(n);
  std::size_t lo = 0, hi = 0;  // the window is [lo, hi)
  for (std::size_t i = 0; i < n; ++i) {
    while (hi < n && stamps_s[hi] - stamps_s[i] <= half_window_s) add(hi++, 1.0);
    while (stamps_s[i] - stamps_s[lo] > half_window_s) add(lo++, -1.0);
    const double count = static_cast<double>(hi - lo);
    const double c = sums.c / count, s = sums.s / count;
    const Pose2& t = tracker_T_base[i];
    const Pose2 in_reference(sums.x / count + c * t.x() - s * t.y(),
                             sums.y / count + s * t.x() + c * t.y(),
                             std::atan2(sums.s, sums.c) + t.theta());
    smoothed[i] = reference * in_reference;
  }
  return smoothed;
}

void SmoothStretches(const std::vector<double>& stamps_s, const std::vector<bool>& in_stretch,
                     const std::vector<Pose2>& chain, double half_window_s,
                     std::vector<Pose2>& map_T_base) {
  const std::size_t n = map_T_base.size();
  for (std::size_t begin = 0; half_window_s > 0.0 && begin < n;) {
    std::size_t end = begin;
    while (end < n && in_stretch[end] && (end == begin || stamps_s[end] >= stamps_s[end - 1])) {
      ++end;
    }
    if (end - begin >= 2) {
      const std::vector<Pose2> smoothed = SmoothAcrossLocalMaps(
          std::vector<double>(stamps_s.begin() + begin, stamps_s.begin() + end),
          std::vector<Pose2>(map_T_base.begin() + begin, map_T_base.begin() + end),
          std::vector<Pose2>(chain.begin() + begin, chain.begin() + end), half_window_s);
      std::copy(smoothed.begin(), smoothed.end(), map_T_base.begin() + begin);
    }
    begin = std::max(end, begin + 1);
  }
}

}  // namespace longterm_mapper2d
