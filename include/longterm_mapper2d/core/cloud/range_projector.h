#pragma once

#include <cmath>
#include <vector>

#include "longterm_mapper2d/core/cloud/rich_point.h"
#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d {

// The angular bins of a range-bearing image. Bin i is centred at angle_min_rad + i * increment,
// as the laser's own beams are, so that a scan's beam i falls exactly into bin i. A full circle
// wraps around: the bins before 0 are the last ones.
struct ProjectorGeometry {
  double angle_min_rad = -M_PI;
  double angle_increment_rad = 2.0 * M_PI / 720.0;
  int num_bins = 720;
  double min_range_m = 0.0;
  double max_range_m = 30.0;
  bool wraps = true;

  static ProjectorGeometry FromScan(const LaserScan& scan, double max_range_m);
  static ProjectorGeometry FullCircle(int num_bins, double max_range_m);

  // The bin of a bearing, or -1 outside the field of view. Inline, with the common cases first:
  // it runs for every point of every projection and association.
  int BinOf(double bearing_rad) const {
    double relative = bearing_rad - angle_min_rad;
    if (wraps) {
      if (!(relative >= 0.0 && relative < 2.0 * M_PI)) {
        relative = std::fmod(relative, 2.0 * M_PI);
        if (relative < 0.0) relative += 2.0 * M_PI;
      }
      const int bin = static_cast<int>(RoundHalfAway(relative / angle_increment_rad));
      return bin >= num_bins ? bin - num_bins : bin;
    }
    // Bearings are continuous across +-pi: measure from the middle of the field of view.
    const double half_fov = 0.5 * angle_increment_rad * (num_bins - 1);
    relative = NormalizeAngle(relative - half_fov) + half_fov;
    const long bin = RoundHalfAway(relative / angle_increment_rad);
    return bin >= 0 && bin < num_bins ? static_cast<int>(bin) : -1;
  }
  // std::lround without the library call: halves away from zero. Exact: x - trunc(x) is
  // representable, so the comparison with one half sees the true fraction.
  static long RoundHalfAway(double x) {
    if (!(std::abs(x) < 1e15)) return std::lround(x);
    const long whole = static_cast<long>(x);
    const double fraction = x - static_cast<double>(whole);
    if (fraction >= 0.5) return whole + 1;
    if (fraction <= -0.5) return whole - 1;
    return whole;
  }
  double BinAngle(int bin) const { return angle_min_rad + angle_increment_rad * bin; }
  // Bin index shifted by `offset`, wrapped for a full circle; -1 if it leaves the field of view.
  int Shift(int bin, int offset) const {
    int shifted = bin + offset;
    if (wraps) {
      shifted %= num_bins;
      if (shifted < 0) shifted += num_bins;
      return shifted;
    }
    return shifted >= 0 && shifted < num_bins ? shifted : -1;
  }
};

// A z-buffer: per bin, the range of the nearest point and the index of that point in its cloud,
// or -1 when the bin is empty or its nearest point faces away from the viewpoint (back faces
// occlude what is behind them but must not be matched).
struct RangeImage {
  std::vector<float> ranges_m;  // +inf where empty
  std::vector<int> indices;     // the nearest point if it faces the viewpoint, else -1
  std::vector<int> nearest;     // the nearest point whichever way it faces, else -1
  void Reset(int num_bins);
};

// Projects `cloud` seen from a viewpoint into `image`: viewpoint_T_cloud maps cloud coordinates
// into the viewpoint frame (x forward). Buffers are reused between calls.
void ProjectCloud(const ProjectorGeometry& geometry, const Pose2& viewpoint_T_cloud,
                  const Cloud& cloud, RangeImage* image);

}  // namespace longterm_mapper2d
