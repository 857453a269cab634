#pragma once

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

  // The bin of a bearing, or -1 outside the field of view.
  int BinOf(double bearing_rad) const;
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
