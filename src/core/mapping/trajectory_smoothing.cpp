#include "longterm_mapper2d/core/mapping/trajectory_smoothing.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>

namespace longterm_mapper2d {

std::vector<Pose2> AverageCorrections(const std::vector<double>& stamps_s,
                                      const std::vector<std::optional<Pose2>>& corrections,
                                      const std::vector<Pose2>& poses, double half_window_s) {
  const std::size_t n = poses.size();
  std::vector<Pose2> averaged = poses;
  std::size_t first = 0;
  while (first < n && !corrections[first]) ++first;
  if (first == n) return averaged;
  // C_j * T_i has the position t_j + R_j t_i and the heading th_j + th_i, so the window needs only
  // the sums of t_j, cos th_j and sin th_j: the mean position is mean(t_j) + mean(R_j) t_i,
  // mean(R_j) the mean of the rotation matrices; the heading is th_i plus the direction of (sum
  // cos, sum sin). Sums are taken relative to the first correction (small numbers, no cancellation
  // far from the origin).
  const Pose2 reference = *corrections[first];
  const Pose2 reference_inverse = reference.inverse();
  struct Sums {
    double x = 0.0, y = 0.0, c = 0.0, s = 0.0;
    int count = 0;
  };
  std::vector<Pose2> relative(n);
  for (std::size_t j = 0; j < n; ++j) {
    if (corrections[j]) relative[j] = reference_inverse * *corrections[j];
  }
  Sums sums;
  auto add = [&](std::size_t j, int sign) {
    if (!corrections[j]) return;
    sums.x += sign * relative[j].x();
    sums.y += sign * relative[j].y();
    sums.c += sign * std::cos(relative[j].theta());
    sums.s += sign * std::sin(relative[j].theta());
    sums.count += sign;
  };
  std::size_t lo = 0, hi = 0;  // the window is [lo, hi)
  for (std::size_t i = 0; i < n; ++i) {
    while (hi < n && stamps_s[hi] - stamps_s[i] <= half_window_s) add(hi++, 1);
    while (stamps_s[i] - stamps_s[lo] > half_window_s) add(lo++, -1);
    if (sums.count <= 0) continue;
    const double count = static_cast<double>(sums.count);
    const double c = sums.c / count, s = sums.s / count;
    const Pose2& t = poses[i];
    const Pose2 in_reference(sums.x / count + c * t.x() - s * t.y(),
                             sums.y / count + s * t.x() + c * t.y(),
                             std::atan2(sums.s, sums.c) + t.theta());
    averaged[i] = reference * in_reference;
  }
  return averaged;
}

std::vector<Pose2> SmoothAcrossLocalMaps(const std::vector<double>& stamps_s,
                                         const std::vector<Pose2>& map_T_base,
                                         const std::vector<Pose2>& tracker_T_base,
                                         double half_window_s) {
  const std::size_t n = map_T_base.size();
  if (half_window_s <= 0.0 || n < 2) return map_T_base;
  // Corrections C_j: map_T_tracker as scan j's node has it.
  std::vector<std::optional<Pose2>> corrections(n);
  for (std::size_t j = 0; j < n; ++j) corrections[j] = map_T_base[j] * tracker_T_base[j].inverse();
  return AverageCorrections(stamps_s, corrections, tracker_T_base, half_window_s);
}

namespace {

// Calls fn(begin, end) for each run of consecutive poses that have `in_stretch` set and
// non-decreasing stamps, two poses or more.
template <class Fn>
void ForEachStretch(const std::vector<double>& stamps_s, const std::vector<bool>& in_stretch,
                    Fn&& fn) {
  const std::size_t n = stamps_s.size();
  for (std::size_t begin = 0; begin < n;) {
    std::size_t end = begin;
    while (end < n && in_stretch[end] && (end == begin || stamps_s[end] >= stamps_s[end - 1])) {
      ++end;
    }
    if (end - begin >= 2) fn(begin, end);
    begin = std::max(end, begin + 1);
  }
}

template <class T>
std::vector<T> Slice(const std::vector<T>& v, std::size_t begin, std::size_t end) {
  return std::vector<T>(v.begin() + begin, v.begin() + end);
}

}  // namespace

void SmoothStretches(const std::vector<double>& stamps_s, const std::vector<bool>& in_stretch,
                     const std::vector<Pose2>& chain, double half_window_s,
                     std::vector<Pose2>& map_T_base) {
  if (half_window_s <= 0.0) return;
  ForEachStretch(stamps_s, in_stretch, [&](std::size_t begin, std::size_t end) {
    const std::vector<Pose2> smoothed =
        SmoothAcrossLocalMaps(Slice(stamps_s, begin, end), Slice(map_T_base, begin, end),
                              Slice(chain, begin, end), half_window_s);
    std::copy(smoothed.begin(), smoothed.end(), map_T_base.begin() + begin);
  });
}

void CorrectStretches(const std::vector<double>& stamps_s, const std::vector<bool>& in_stretch,
                      const std::vector<std::optional<Pose2>>& corrections, double half_window_s,
                      std::vector<Pose2>& map_T_base) {
  ForEachStretch(stamps_s, in_stretch, [&](std::size_t begin, std::size_t end) {
    const std::vector<Pose2> corrected =
        AverageCorrections(Slice(stamps_s, begin, end), Slice(corrections, begin, end),
                           Slice(map_T_base, begin, end), half_window_s);
    std::copy(corrected.begin(), corrected.end(), map_T_base.begin() + begin);
  });
}

}  // namespace longterm_mapper2d
