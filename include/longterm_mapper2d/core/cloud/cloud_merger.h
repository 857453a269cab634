#pragma once

#include <vector>

#include "longterm_mapper2d/core/cloud/range_projector.h"
#include "longterm_mapper2d/core/cloud/rich_point.h"
#include "longterm_mapper2d/core/config/option_errors.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d {

struct MergerOptions {
  // Off: plain accumulation for comparison (new points are added or fused; nothing a beam passed
  // through is replaced or erased), as a map without free-space reasoning would keep people.
  bool free_space_reasoning = true;
  // Points of the two clouds closer than this along a beam are the same surface.
  double merge_distance_m = 0.2;
  // Normals farther apart than this are different surfaces (no fusion).
  double merge_normal_angle_rad = 1.0;
  // Fuse points that pile up along one ray into the bin's nearest point.
  bool radial_merge = true;
  // A no-return beam proves free space up to this range (it went at least that far).
  double free_space_max_range_m = 10.0;
  // Accumulated weights saturate here, so old evidence cannot outvote new observations forever.
  double max_weight = 1000.0;
  // A fused return farther than static_distance_m + static_distance_per_m * range from the old
  // point's line (along its normal) means the surface moved: the fused point has 0 observations.
  // The range term covers the pose's rotation error, which moves far points.
  double static_distance_m = 0.04;
  double static_distance_per_m = 0.005;

  template <class V>
  void Visit(V& v) {
    v("free_space_reasoning", free_space_reasoning);
    v("merge_distance_m", merge_distance_m);
    v("merge_normal_angle_rad", merge_normal_angle_rad);
    v("radial_merge", radial_merge);
    v("free_space_max_range_m", free_space_max_range_m);
    v("max_weight", max_weight);
    v("static_distance_m", static_distance_m);
    v("static_distance_per_m", static_distance_per_m);
  }
  void Validate(OptionErrors& e) const {
    e.Require(merge_distance_m > 0.0, "merge_distance_m", "must be positive");
    e.Require(merge_normal_angle_rad > 0.0 && merge_normal_angle_rad <= M_PI,
              "merge_normal_angle_rad", "must be in (0, pi]");
    e.Require(free_space_max_range_m >= 0.0, "free_space_max_range_m", "must be non-negative");
    e.Require(max_weight > 0.0, "max_weight", "must be positive");
    e.Require(static_distance_m > 0.0, "static_distance_m", "must be positive");
    e.Require(static_distance_per_m >= 0.0, "static_distance_per_m", "must be non-negative");
  }
};

struct MergeStats {
  int added = 0;     // new points (new surface, or in front of the old one)
  int fused = 0;     // same surface: weighted average
  int replaced = 0;  // an old point the new beam passed through, replaced by the new return
  int erased = 0;    // old points a beam passed through with nothing behind (free space)
  int thinned = 0;   // fused by the radial merge
};

// Weighted fusion of two points: position and normal averaged with the accumulated weights
// (1/r at creation), weights summed and saturated at max_weight; observation counts summed.
RichPoint Fuse(const RichPoint& a, const RichPoint& b, double max_weight);

// Merges a new scan into a map cloud, bin by bin as seen from the laser (see ALGORITHMS.md §5):
// with d = r_map - r_new in a beam's bin,
//   no map point            -> the new point is added;
//   d > tau                 -> the new point is in front of the old one: added, the old one kept;
//   d < -tau                -> the beam passed through the old point: it is replaced;
//   |d| <= tau              -> the same surface: fused if the normals agree, with one more
//                              observation if the return lies within the static distance of the
//                              old point's line, and 0 otherwise (it moved);
//   no new return           -> the old point is erased only if the beam proves free space past it
//                              (a no-return beam up to free_space_max_range_m, or a return
//                              farther than the cloud's range); bins the scan did not observe
//                              (invalid readings, outside the field of view) are never touched.
// Observation counts (RichPoint::observations): a point added to an empty bin starts at 1; one
// added in front of an old point or replacing one starts at 0 (it appeared where a beam had
// passed, or where something was), so moving things never reach the tracker's target threshold.
// `map` and `scan_points` are in one frame F, frame_T_laser is the laser pose in F, and
// `scan_beams[i]` is the beam of scan_points[i].
class CloudMerger {
 public:
  explicit CloudMerger(const MergerOptions& options) : options_(options) {}
  MergeStats Merge(Cloud& map, const Cloud& scan_points, const std::vector<int>& scan_beams,
                   const LaserScan& scan, const Pose2& frame_T_laser, double max_point_range_m);
  // Free space alone, for a cloud that no longer takes new points (a finished node's snapshot):
  // erases the points with at most max_observations observations that a beam of `scan` passed
  // through, i.e. the bin's nearest point lies more than merge_distance_m in front of where the
  // beam ended (its return, or free_space_max_range_m for a no-return beam). Invalid readings
  // observe nothing. Returns the number erased.
  int EraseSeenThrough(Cloud& map, const LaserScan& scan, const Pose2& frame_T_laser,
                       int max_observations);
  // Removes map points farther than range_m from `centre`.
  static void Clip(Cloud& map, const Eigen::Vector2d& centre, double range_m);

 private:
  int RadialMerge(Cloud& map, const ProjectorGeometry& geometry, const Pose2& laser_T_frame);
  MergerOptions options_;
  RangeImage image_;
  std::vector<char> remove_;
  std::vector<int> src_of_beam_;
};

}  // namespace longterm_mapper2d
