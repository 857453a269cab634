#pragma once

#include "longterm_mapper2d/core/cloud/rich_point.h"
#include "longterm_mapper2d/core/config/option_errors.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d {

struct CloudOptions {
  // Neighbours of a point for its normal: consecutive returns within this radius, or within
  // normal_radius_beams beam spacings at the point's range where that is wider: far from the
  // laser the beams fan out (1 deg apart: 0.15 m at 8.6 m, 0.35 m at 20 m), and a fixed radius
  // would leave the far walls of a large hall without a single normal (0: fixed radius).
  double normal_radius_m = 0.3;
  double normal_radius_beams = 0.0;
  int normal_min_points = 5;
  // A neighbourhood is a line if lambda_min / lambda_max is below this; otherwise (a corner, a
  // blob of clutter) the point gets no normal.
  double normal_max_curvature = 0.1;
  // Returns beyond this are not turned into points (they still count as free space).
  double max_range_m = 30.0;

  template <class V>
  void Visit(V& v) {
    v("normal_radius_m", normal_radius_m);
    v("normal_radius_beams", normal_radius_beams);
    v("normal_min_points", normal_min_points);
    v("normal_max_curvature", normal_max_curvature);
    v("max_range_m", max_range_m);
  }
  void Validate(OptionErrors& e) const {
    e.Require(normal_radius_m > 0.0, "normal_radius_m", "must be positive");
    e.Require(normal_radius_beams >= 0.0, "normal_radius_beams", "must be non-negative");
    e.Require(normal_min_points >= 2, "normal_min_points", "must be at least 2");
    e.Require(normal_max_curvature > 0.0 && normal_max_curvature <= 1.0, "normal_max_curvature",
              "must be in (0, 1]");
    e.Require(max_range_m > 0.0, "max_range_m", "must be positive");
  }
};

// The valid returns of a scan as points in the laser frame (weight 1/r, no normals yet), with the
// beam index of every point.
Cloud PointsFromScan(const LaserScan& scan, const CloudOptions& options, std::vector<int>* beams);
// Normals from the smallest eigenvector of each point's neighbourhood (consecutive points within
// normal_radius_m, or normal_radius_beams x range x |angle_increment_rad| if wider), facing the
// origin of the cloud's frame (the laser). An increment of 0 keeps the radius fixed.
void EstimateNormals(Cloud& laser_points, const CloudOptions& options,
                     double angle_increment_rad = 0.0);

// Turns the valid returns of a scan into points in the base frame (base_T_laser applied), each
// with weight 1/r and a normal facing the laser, or a zero normal where the neighbourhood is too
// small or not a line. If `beam_of_point` is given, it receives the beam index of every point.
Cloud CloudFromScan(const LaserScan& scan, const Pose2& base_T_laser, const CloudOptions& options,
                    std::vector<int>* beam_of_point = nullptr);

}  // namespace longterm_mapper2d
