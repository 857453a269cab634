#pragma once

#include <Eigen/Core>
#include <optional>

#include "longterm_mapper2d/core/cloud/cloud_merger.h"
#include "longterm_mapper2d/core/cloud/range_projector.h"
#include "longterm_mapper2d/core/config/mapper_options.h"
#include "longterm_mapper2d/core/mapping/mapper_stats.h"
#include "longterm_mapper2d/core/mapping/motion_filter.h"
#include "longterm_mapper2d/core/registration/nicp.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"

namespace longterm_mapper2d {

struct TrackResult {
  Pose2 tracker_T_base;
  bool registered = false;  // scan matching ran and was accepted
  bool failed = false;      // scan matching ran and was rejected: the local map was reset
  // Covariance of the step prev_T_base, in the previous base frame (additive x, y, theta): for
  // the optimiser's odometry edges, and for the loop closer's candidate gate (the same unless
  // TrackerOptions::tight_odometry_edges).
  Eigen::Matrix3d step_covariance = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d gating_step_covariance = Eigen::Matrix3d::Identity();
};

// Odometry noise of one step, as a covariance in the robot frame (TrackerOptions' model).
Eigen::Matrix3d OdometryStepCovariance(const Pose2& step, const TrackerOptions& options);

// Scan-to-local-map tracking (ALGORITHMS.md §4.1): each scan is registered against a local map
// kept in the tracker's own frame, with odometry as prior; accepted scans are merged into the map
// with the free-space rules; a rejected registration resets the local map to the scan and dead
// reckons.
class Tracker {
 public:
  explicit Tracker(const MapperOptions& options);

  bool initialized() const { return initialized_; }
  // Starts (or restarts) the local map from this scan at tracker_T_base.
  void Reset(const ScanInput& input, const Pose2& tracker_T_base, MapperStats& stats);
  // Tracks one scan given the guess (previous estimate composed with the odometry step).
  TrackResult Track(const ScanInput& input, const Pose2& previous_tracker_T_base,
                    const Pose2& odometry_step, MapperStats& stats);

  // Registers a scan the mapper does not process (too little motion since the last processed one)
  // against the local map, for its pose only: the local map, the motion filter and the last
  // processed pose stay as they are. The pose if the registration is accepted, else nothing;
  // nothing as well while odometry is good (TrackerOptions::locate_min_correction_m / _rad).
  std::optional<Pose2> Locate(const ScanInput& input, const Pose2& previous_tracker_T_base,
                              const Pose2& odometry_step, MapperStats& stats);

  // The local map, in the tracker frame.
  const Cloud& local_map() const { return local_map_; }

 private:
  Cloud MakeCloud(const ScanInput& input, std::vector<int>* beams, MapperStats& stats) const;
  void MergeIntoLocalMap(const ScanInput& input, const Cloud& base_points,
                         const std::vector<int>& beams, const Pose2& tracker_T_base,
                         MapperStats& stats);
  // kTrack: a processed scan; targets chosen for it, retried without the odometry prior if it
  // does not validate, validated against the whole local map. kLocate: a skipped scan; the last
  // processed scan's targets, no retry, the whole local map only if the targets do not validate.
  enum class RegistrationMode { kTrack, kLocate };
  // The last try before a failure: alignments without the prior from turned guesses
  // (TrackerOptions::failure_heading_steps), a degenerate one again holding odometry's position
  // (failure_heading_min_information_ratio); the best validated one, or an unaccepted result.
  RegistrationResult AlignTurned(const ScanInput& input, const Cloud& base_points,
                                 const Cloud& targets, const Pose2& guess,
                                 const Pose2& odometry_step, const ProjectorGeometry& geometry,
                                 MapperStats& stats);
  // Registers base_points (the scan's cloud) against the local map from guess, with the odometry
  // prior of the step if configured.
  RegistrationResult Register(const ScanInput& input, const Cloud& base_points, const Pose2& guess,
                              const Pose2& odometry_step, RegistrationMode mode,
                              MapperStats& stats);
  // Marks the scan points of things seen moving (MotionFilter) and keeps the scan as a reference.
  void MarkMovingPoints(const ScanInput& input, Cloud& base_points, MapperStats& stats);
  // The local map's points used as registration targets (TrackerOptions::min_target_observations)
  // for a scan taken from tracker_T_laser.
  const Cloud& RegistrationTargets(const Pose2& tracker_T_laser, const ProjectorGeometry& geometry);

  MapperOptions options_;
  Nicp nicp_;
  CloudMerger merger_;
  MotionFilter motion_filter_;
  Cloud local_map_;
  std::vector<char> moving_;           // per scan point, from motion_filter_
  Cloud targets_;                      // reused buffers of RegistrationTargets()
  bool targets_are_local_map_ = true;  // the last processed scan's targets: local_map_ or targets_
  // Moving averages of how far registration moved odometry's guess (processed scans); until the
  // first, every skipped scan is located.
  bool corrections_seen_ = false;
  double mean_correction_m_ = 0.0;
  double mean_correction_rad_ = 0.0;
  RangeImage view_;
  bool initialized_ = false;
  Eigen::Vector2d last_clip_position_ = Eigen::Vector2d::Zero();
};

}  // namespace longterm_mapper2d
