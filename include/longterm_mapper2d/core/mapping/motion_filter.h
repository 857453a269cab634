#pragma once

#include <deque>
#include <vector>

#include "longterm_mapper2d/core/cloud/range_projector.h"
#include "longterm_mapper2d/core/cloud/rich_point.h"
#include "longterm_mapper2d/core/config/option_errors.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d {

struct MotionFilterOptions {
  // Off: every scan point may be a registration target once seen in place (the merger's test only).
  bool enabled = true;
  // A scan is compared with the oldest earlier scan at most max_age_s old (odometry drifts) and
  // at least min_baseline_s old: a person walking at 0.3 m/s has moved 0.6 m in 2 s, where
  // between two consecutive scans it moves no more than the laser's noise.
  double min_baseline_s = 0.5;
  double max_age_s = 2.0;
  // A point is moving if every beam of the earlier scan within window_rad of its bearing went
  // farther than its range plus min_distance_m + distance_per_m * range (the margin covers range
  // noise and the odometry's error over the baseline; the window, its heading error).
  double min_distance_m = 0.13;
  double distance_per_m = 0.01;
  double window_rad = 0.0175;
  // Odometry's error between the two scans, per metre travelled and per radian turned: added to
  // the margin (per metre travelled; per radian turned, times the range) and to the window.
  double odometry_error_per_m = 0.15;
  double odometry_error_per_rad = 0.1;
  // Points are judged per object (a run of scan points without a gap of max_gap_m): an object at
  // most max_object_m across, of at least min_object_points points, most of which moved, moves
  // as a whole (a person's edges are seen at grazing angles, where the test is weak).
  double max_gap_m = 0.15;
  double max_object_m = 1.0;
  int min_object_points = 3;
  // A beam with no return went at least this far.
  double no_return_free_m = 10.0;
  // More than this share of a scan's points with evidence of motion (before pooling per object)
  // means odometry, not the world, moved (a kidnapped robot, wheels slipping): nothing is marked.
  double max_moving_fraction = 0.3;

  template <class V>
  void Visit(V& v) {
    v("enabled", enabled);
    v("min_baseline_s", min_baseline_s);
    v("max_age_s", max_age_s);
    v("min_distance_m", min_distance_m);
    v("distance_per_m", distance_per_m);
    v("window_rad", window_rad);
    v("odometry_error_per_m", odometry_error_per_m);
    v("odometry_error_per_rad", odometry_error_per_rad);
    v("max_gap_m", max_gap_m);
    v("max_object_m", max_object_m);
    v("min_object_points", min_object_points);
    v("no_return_free_m", no_return_free_m);
    v("max_moving_fraction", max_moving_fraction);
  }
  void Validate(OptionErrors& e) const {
    e.Require(min_baseline_s > 0.0, "min_baseline_s", "must be positive");
    e.Require(max_age_s >= min_baseline_s, "max_age_s", "must be at least min_baseline_s");
    e.Require(min_distance_m > 0.0, "min_distance_m", "must be positive");
    e.Require(distance_per_m >= 0.0, "distance_per_m", "must be non-negative");
    e.Require(window_rad >= 0.0 && window_rad < M_PI, "window_rad", "must be in [0, pi)");
    e.Require(odometry_error_per_m >= 0.0 && odometry_error_per_rad >= 0.0, "odometry_error_per_m",
              "odometry error slopes must be non-negative");
    e.Require(max_gap_m > 0.0, "max_gap_m", "must be positive");
    e.Require(max_object_m >= 0.0, "max_object_m", "must be non-negative");
    e.Require(min_object_points >= 1, "min_object_points", "must be at least 1");
    e.Require(no_return_free_m >= 0.0, "no_return_free_m", "must be non-negative");
    e.Require(max_moving_fraction >= 0.0 && max_moving_fraction <= 1.0, "max_moving_fraction",
              "must be in [0, 1]");
  }
};

// Finds the scan points of things that moved, mostly people: points standing where an earlier
// scan saw free space (moved in), and small objects first seen behind something that has left
// the place where it hid them (a person walking away). The earlier scan is placed by odometry
// alone, so the test does not depend on the registration it protects: a slow walker that the scan
// matcher has started to follow looks static in the tracker's frame, but not in odometry's.
class MotionFilter {
 public:
  explicit MotionFilter(const MotionFilterOptions& options) : options_(options) {}

  // Marks (*moving)[i] for each point of base_points (in the base frame of `input`) in free space
  // of the reference scan; returns how many. Marks nothing without a reference scan or when too
  // much seems to move.
  int FindMoving(const ScanInput& input, const Cloud& base_points, std::vector<char>* moving);
  // Keeps the scan as a future reference.
  void Remember(const ScanInput& input);
  // Forgets every reference (odometry found wrong, time went backwards).
  void Clear() { history_.clear(); }

 private:
  struct Reference {
    double stamp_s;
    Pose2 odom_T_laser;
    LaserScan scan;
    ProjectorGeometry geometry;
  };
  const Reference* ReferenceFor(double stamp_s);
  // Extends the marks to small objects (runs of consecutive points) holding a marked point.
  int MarkObjects(const Cloud& base_points, std::vector<char>* moving) const;
  // How far every beam of `scan` within window_rad of the bearing went (0: unknown).
  double FreeRange(const LaserScan& scan, const ProjectorGeometry& geometry, double bearing_rad,
                   double window_rad) const;

  MotionFilterOptions options_;
  std::deque<Reference> history_;
};

}  // namespace longterm_mapper2d
