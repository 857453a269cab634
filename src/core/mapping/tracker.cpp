#include "longterm_mapper2d/core/mapping/tracker.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "longterm_mapper2d/core/cloud/range_projector.h"
#include "longterm_mapper2d/core/cloud/scan_to_cloud.h"

namespace longterm_mapper2d {

Eigen::Matrix3d OdometryStepCovariance(const Pose2& step, const TrackerOptions& o) {
  const double d = step.translation().norm();
  const double sigma_xy = o.odometry_sigma_xy_m + o.odometry_sigma_xy_per_m * d;
  const double sigma_theta = o.odometry_sigma_theta_rad +
                             o.odometry_sigma_theta_per_rad * std::abs(step.theta()) +
                             o.odometry_sigma_theta_per_m * d;
  return Eigen::Vector3d(sigma_xy * sigma_xy, sigma_xy * sigma_xy, sigma_theta * sigma_theta)
      .asDiagonal();
}

Tracker::Tracker(const MapperOptions& options)
    : options_(options),
      nicp_(options.registration),
      merger_(options.merger),
      motion_filter_(options.motion_filter) {}

Cloud Tracker::MakeCloud(const ScanInput& input, std::vector<int>* beams,
                         MapperStats& stats) const {
  Cloud laser_points;
  {
    ScopedStageTimer timer(stats.stage_times, "conversion");
    laser_points = PointsFromScan(input.scan, options_.cloud, beams);
  }
  ScopedStageTimer timer(stats.stage_times, "normals");
  EstimateNormals(laser_points, options_.cloud, input.scan.angle_increment_rad);
  return Transform(input.base_T_laser, laser_points);
}

void Tracker::Reset(const ScanInput& input, const Pose2& tracker_T_base, MapperStats& stats) {
  std::vector<int> beams;
  const Cloud base_points = MakeCloud(input, &beams, stats);
  local_map_ = Transform(tracker_T_base, base_points);
  targets_are_local_map_ = true;  // the targets of the map before are gone with it
  motion_filter_.Remember(input);
  initialized_ = true;
  last_clip_position_ = tracker_T_base.translation();
}

void Tracker::MergeIntoLocalMap(const ScanInput& input, const Cloud& base_points,
                                const std::vector<int>& beams, const Pose2& tracker_T_base,
                                MapperStats& stats) {
  ScopedStageTimer timer(stats.stage_times, "merging");
  const Cloud points = Transform(tracker_T_base, base_points);
  const MergeStats merged =
      merger_.Merge(local_map_, points, beams, input.scan, tracker_T_base * input.base_T_laser,
                    options_.cloud.max_range_m);
  stats.counters["points_erased_free_space"] += merged.erased;
  stats.counters["points_replaced"] += merged.replaced;
  if ((tracker_T_base.translation() - last_clip_position_).norm() >=
      options_.tracker.clip_every_m) {
    CloudMerger::Clip(local_map_, tracker_T_base.translation(), options_.tracker.local_map_range_m);
    last_clip_position_ = tracker_T_base.translation();
  }
}

const Cloud& Tracker::RegistrationTargets(const Pose2& tracker_T_laser,
                                          const ProjectorGeometry& geometry) {
  const int min_observations = options_.tracker.min_target_observations;
  if (min_observations <= 0) return local_map_;
  // What the scan will see: of the local map's surfaces in view (the nearest point per beam), how
  // many are confirmed? Turning into new space, or a fresh local map, leaves few; then the points
  // seen once count too, and only those seen moving are left out.
  ProjectCloud(geometry, tracker_T_laser.inverse(), local_map_, &view_);
  int in_view = 0, confirmed = 0;
  for (const int index : view_.indices) {
    if (index < 0) continue;
    ++in_view;
    if (local_map_[index].observations >= min_observations) ++confirmed;
  }
  const bool enough_confirmed =
      in_view > 0 && confirmed >= options_.tracker.min_stable_target_fraction * in_view;
  const int needed = enough_confirmed ? min_observations : 1;
  targets_.clear();
  for (const RichPoint& p : local_map_) {
    if (p.observations >= needed) targets_.push_back(p);
  }
  // Nearly everything seen moving (a crowd filling the view): better the whole map than nothing.
  if (static_cast<int>(targets_.size()) < options_.registration.min_correspondences) {
    return local_map_;
  }
  return targets_;
}

void Tracker::MarkMovingPoints(const ScanInput& input, Cloud& base_points, MapperStats& stats) {
  // Things odometry saw move since an earlier scan enter the local map as seen moving
  // (observations 0), so they never become registration targets, however slowly they walk. They
  // still take part in this scan's registration: without targets of their own they pair with
  // little. (Leaving them out of it as well made the real logs' loop closing worse: intel 0.05 ->
  // 0.24 m, aces 0.05 -> 0.40 m.)
  const int moving = motion_filter_.FindMoving(input, base_points, &moving_);
  motion_filter_.Remember(input);
  if (moving == 0) return;
  stats.counters["points_seen_moving"] += moving;
  for (std::size_t i = 0; i < base_points.size(); ++i) {
    if (moving_[i]) base_points[i].observations = 0;
  }
}

RegistrationResult Tracker::Register(const ScanInput& input, const Cloud& base_points,
                                     const Pose2& guess, const Pose2& odometry_step,
                                     RegistrationMode mode, MapperStats& stats) {
  const bool locating = mode == RegistrationMode::kLocate;
  std::optional<PosePrior> prior;
  if (options_.tracker.odometry_prior) {
    // The odometry model is for the step in the robot frame; with the error in the tracker frame
    // its information is carried over by the adjoint of guess^-1.
    const Eigen::Matrix3d step_information =
        OdometryStepCovariance(odometry_step, options_.tracker).inverse();
    if (options_.tracker.odometry_prior_robot_frame) {
      prior = PosePrior{guess, step_information, true};
    } else {
      const Eigen::Matrix3d ad = Adjoint(guess.inverse());
      prior = PosePrior{guess, ad.transpose() * step_information * ad, false};
    }
  }
  ScopedStageTimer timer(stats.stage_times, "registration");
  const ProjectorGeometry geometry =
      ProjectorGeometry::FromScan(input.scan, options_.cloud.max_range_m);
  // A located scan is matched against the targets of the last processed scan: the local map has
  // not changed since (only that scan's own points are missing), and choosing targets again
  // would project the whole local map once more.
  const Cloud& targets = locating ? (targets_are_local_map_ ? local_map_ : targets_)
                                  : RegistrationTargets(guess * input.base_T_laser, geometry);
  if (!locating) targets_are_local_map_ = &targets == &local_map_;
  // A located scan's guess is within a few centimetres of the result (odometry over less than
  // the processing threshold): validated from there, without projecting the targets again.
  RegistrationResult registration = nicp_.AlignProjective(
      targets, base_points, guess, input.base_T_laser, geometry, prior,
      locating ? Nicp::ValidationView::kFromGuess : Nicp::ValidationView::kFromResult);
  stats.counters["registration_targets_seen_through"] += registration.seen_through;
  if (!locating && prior && !registration.validation.accepted) {
    // Odometry can be badly wrong for a step (wheel slip, turning in place): let the scan
    // decide alone before giving up on the local map.
    ++stats.counters["registrations_retried_without_prior"];
    registration = nicp_.AlignProjective(targets, base_points, guess, input.base_T_laser, geometry,
                                         std::nullopt);
    // The earlier scans were placed by the odometry that just failed.
    if (registration.validation.accepted) motion_filter_.Clear();
  }
  // A located scan that fits the targets is taken as it is (one projection of the local map
  // less); the whole local map is the second chance.
  const bool done = locating && registration.validation.accepted;
  if (&targets != &local_map_ && registration.solved && !done) {
    // Judged against everything the local map saw: areas seen once (just come into view)
    // are not targets yet, but they are evidence that the scan fits.
    registration.validation =
        nicp_.Validate(local_map_, base_points, registration.reference_T_current,
                       registration.reference_T_current * input.base_T_laser, geometry);
  }
  // Turning in place, odometry's heading can be off by more than the alignment reaches; a
  // failure would keep that error in the new local map for good (intel: 28 deg).
  if (!locating && !registration.validation.accepted &&
      options_.tracker.failure_heading_steps > 0) {
    RegistrationResult turned =
        AlignTurned(input, base_points, targets, guess, odometry_step, geometry, stats);
    if (turned.validation.accepted) {
      motion_filter_.Clear();
      registration = std::move(turned);
    }
  }
  return registration;
}

RegistrationResult Tracker::AlignTurned(const ScanInput& input, const Cloud& base_points,
                                        const Cloud& targets, const Pose2& guess,
                                        const Pose2& odometry_step,
                                        const ProjectorGeometry& geometry, MapperStats& stats) {
  RegistrationResult best;
  const int steps = options_.tracker.failure_heading_steps;
  // Odometry's position, for turned alignments that pin the position in one direction only:
  // the position part of the step covariance in the robot frame, e = R_guess^T (t - t_guess),
  // no heading term (the heading is what the retries doubt).
  Eigen::Matrix3d position_information = Eigen::Matrix3d::Zero();
  position_information.topLeftCorner<2, 2>() =
      OdometryStepCovariance(odometry_step, options_.tracker).topLeftCorner<2, 2>().inverse();
  const PosePrior position_prior{guess, position_information, /*robot_frame=*/true};
  for (int step = -steps; step <= steps; ++step) {
    if (step == 0) continue;
    ++stats.counters["registrations_retried_turned"];  // one per turned alignment
    const Pose2 turned = guess * Pose2(0.0, 0.0, step * options_.tracker.failure_heading_step_rad);
    RegistrationResult registration = nicp_.AlignProjective(
        targets, base_points, turned, input.base_T_laser, geometry, std::nullopt);
    if (!registration.solved || !registration.validation.accepted) continue;
    // Without a prior, a scan along a corridor is anywhere along it: in the simulated care home
    // with a 180 deg laser one came out 2.9 m from odometry's position along a corridor and
    // validated (eigenvalue ratio 1e-5; the rest of the patrol stayed 2.5-2.8 m off). Such a
    // result is aligned again holding odometry's position (the rescues on intel, aces and fr079
    // read ratios of 0.08-0.44 and are untouched; held, a bare corridor's position along it
    // comes from odometry alone).
    if (!(PositionInformationRatio(registration.information) >
          options_.tracker.failure_heading_min_information_ratio)) {
      ++stats.counters["registrations_turned_degenerate"];
      registration = nicp_.AlignProjective(targets, base_points, turned, input.base_T_laser,
                                           geometry, position_prior);
      if (!registration.solved || !registration.validation.accepted) continue;
    }
    if (!best.validation.accepted ||
        registration.validation.inlier_ratio > best.validation.inlier_ratio) {
      best = std::move(registration);
    }
  }
  if (best.validation.accepted) ++stats.counters["registrations_rescued_turned"];
  return best;
}

std::optional<Pose2> Tracker::Locate(const ScanInput& input, const Pose2& previous_tracker_T_base,
                                     const Pose2& odometry_step, MapperStats& stats) {
  if (!initialized_ || !options_.tracker.scan_matching) return std::nullopt;
  if (corrections_seen_ && mean_correction_m_ < options_.tracker.locate_min_correction_m &&
      mean_correction_rad_ < options_.tracker.locate_min_correction_rad) {
    ++stats.counters["skipped_scans_dead_reckoned"];
    return std::nullopt;
  }
  const Cloud base_points = MakeCloud(input, nullptr, stats);
  // No retry without the prior: a step this short that odometry got badly wrong is better dead
  // reckoned than matched alone (the next processed scan decides).
  const RegistrationResult registration =
      Register(input, base_points, previous_tracker_T_base * odometry_step, odometry_step,
               RegistrationMode::kLocate, stats);
  if (!registration.solved || !registration.validation.accepted ||
      !registration.reference_T_current.IsFinite()) {
    ++stats.counters["skipped_scans_not_located"];
    return std::nullopt;
  }
  ++stats.counters["skipped_scans_located"];
  return registration.reference_T_current;
}

TrackResult Tracker::Track(const ScanInput& input, const Pose2& previous_tracker_T_base,
                           const Pose2& odometry_step, MapperStats& stats) {
  TrackResult result;
  const Pose2 guess = previous_tracker_T_base * odometry_step;
  result.tracker_T_base = guess;
  result.step_covariance = OdometryStepCovariance(odometry_step, options_.tracker);
  result.gating_step_covariance = result.step_covariance;
  if (!options_.tracker.scan_matching) return result;

  std::vector<int> beams;
  Cloud base_points = MakeCloud(input, &beams, stats);
  MarkMovingPoints(input, base_points, stats);
  const RegistrationResult registration =
      Register(input, base_points, guess, odometry_step, RegistrationMode::kTrack, stats);
  if (!registration.solved || !registration.validation.accepted ||
      !registration.reference_T_current.IsFinite()) {
    ++stats.counters["tracker_failures"];
    Reset(input, guess, stats);
    result.failed = true;
    return result;
  }
  result.registered = true;
  result.tracker_T_base = registration.reference_T_current;
  // How far registration moves odometry's guess, on average over the last ~20 processed scans.
  const Pose2 correction = guess.Between(registration.reference_T_current);
  const double rate = corrections_seen_ ? 0.05 : 1.0;
  corrections_seen_ = true;
  mean_correction_m_ += rate * (correction.translation().norm() - mean_correction_m_);
  mean_correction_rad_ +=
      rate * (std::abs(NormalizeAngle(correction.theta())) - mean_correction_rad_);
  // Covariance of the new pose in its own frame, scaled (the Hessian is optimistic), as the
  // covariance of the step from the previous pose (which the local map already contains).
  const Eigen::Matrix3d ad = Adjoint(result.tracker_T_base.inverse());
  const auto to_step_covariance =
      [&ad](const Eigen::Matrix3d& information) -> std::optional<Eigen::Matrix3d> {
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(information);
    if (!lu.isInvertible()) return std::nullopt;
    const Eigen::Matrix3d covariance = ad * lu.inverse() * ad.transpose();
    return Eigen::Matrix3d(0.5 * (covariance + covariance.transpose()));
  };
  const double scale = options_.tracker.registration_covariance_scale;
  if (const auto loose = to_step_covariance(registration.information / scale)) {
    result.step_covariance = result.gating_step_covariance = *loose;
  }
  // Tight: Omega = (H - H_prior) / scale + H_prior, the prior's share left unscaled. H - H_prior
  // is the scan's sum of J' Omega_i J terms (positive semi-definite), H_prior positive definite.
  const Eigen::Matrix3d& prior_information = registration.prior_information;
  if (options_.tracker.tight_odometry_edges && !prior_information.isZero(0.0)) {
    const Eigen::Matrix3d scan_information = registration.information - prior_information;
    if (const auto tight = to_step_covariance(scan_information / scale + prior_information)) {
      result.step_covariance = *tight;
    }
  }
  MergeIntoLocalMap(input, base_points, beams, result.tracker_T_base, stats);
  return result;
}

}  // namespace longterm_mapper2d
