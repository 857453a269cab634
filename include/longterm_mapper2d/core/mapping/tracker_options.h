#pragma once

#include "longterm_mapper2d/core/config/option_errors.h"

namespace longterm_mapper2d {

// Scan-to-local-map tracking and local-map (node) creation.
struct TrackerOptions {
  // Off: dead reckoning (odometry only), the baseline.
  bool scan_matching = true;
  // A scan is processed once odometry moved this much since the last processed scan.
  double min_translation_m = 0.1;
  double min_rotation_rad = 0.1;
  // The scans in between are still registered against the local map for their own pose (not
  // merged into it, not moving the odometry chain); off, they are dead reckoned from the last
  // processed scan. Their poses are the trajectory's and the published map -> odom between
  // processed scans: with intel's odometry, dead reckoning over up to 0.1 m / 0.1 rad is what
  // limited the trajectory's short-range accuracy.
  bool locate_skipped_scans = true;
  // ... while registration corrects odometry's guess by at least this much per processed scan (a
  // moving average over ~20 scans, either term): with odometry that good, a scan dead reckoned
  // from the last processed one is off by less, and locating it costs time for nothing. Measured
  // per processed scan (~0.1 m): intel 16 mm / 18 mrad, aces 12 / 11, fr079 26 / 23, the
  // simulated care home (2 % slip) 3.2 mm / 1.1 mrad.
  double locate_min_correction_m = 0.005;
  double locate_min_correction_rad = 0.005;
  // The local map keeps points within this range of the robot, clipped every clip_every_m.
  double local_map_range_m = 5.0;
  double clip_every_m = 2.0;
  // A new node (local map) every so much motion, and on tracker failure.
  double node_translation_m = 2.5;
  double node_rotation_rad = 1.0;
  // Odometry model of the registration prior and of dead reckoning, per step in the robot frame:
  // sigma_xy = xy_m + xy_per_m * |d|, sigma_theta = theta_rad + theta_per_rad * |dtheta|
  // + theta_per_m * |d|.
  bool odometry_prior = true;
  // The prior's error taken in the robot's frame (mean^-1 * T) rather than in the tracker frame
  // (T * mean^-1; the tracker frame is the odometry frame). The same to first order, but the
  // tracker-frame error's second order term grows with the distance from the odometry origin:
  // on MIT Killian (350 m from it on average) the tracker turned 5.6 % short of the relations
  // with it and 1.1 % short in the robot frame. Off by default: on intel / aces the robot frame
  // maps intel at 0.030 m (0.040) but broke 5 of 22 perturbed runs whose loop closing held (README
  // "Accuracy", 2026-12-05).
  bool odometry_prior_robot_frame = false;
  double odometry_sigma_xy_m = 0.05;
  double odometry_sigma_xy_per_m = 0.2;
  double odometry_sigma_theta_rad = 0.1;
  double odometry_sigma_theta_per_rad = 1.0;
  double odometry_sigma_theta_per_m = 0.05;
  // Registration targets: only local-map points seen in place by at least this many scans
  // (RichPoint::observations; 0 turns the filter off), so a person walking along a corridor,
  // re-observed a little farther each scan, cannot drag the match along the corridor's free axis.
  // If fewer than min_stable_target_fraction of the surfaces in view qualify (turning into new
  // space, a fresh local map), points seen once are used too; points seen moving never are.
  int min_target_observations = 2;
  double min_stable_target_fraction = 0.5;
  // Registration covariances (inverse Hessians) are optimistic; they are scaled by this before
  // they accumulate into odometry edges.
  double registration_covariance_scale = 100.0;
  // The scale is for the scan's share of the registration information; the odometry prior's
  // share is a calibrated model, not an optimistic Hessian. With this on, the odometry edges the
  // optimiser uses take the scan's information scaled and the prior's as it is (tight), while the
  // loop closer's candidate gate keeps everything scaled (loose: wide marginals find loops after
  // large drift, which the tight edges alone missed on intel's first big loop). Intel, 25 runs at
  // other node / scan spacings: runs with an error over 0.5 m 5 -> 1, mean 0.0319 -> 0.0317 m;
  // care home trajectories 0.037-0.047 -> 0.030-0.039 m in 9 of 10 sessions (README "Accuracy").
  bool tight_odometry_edges = true;
  // A node's cloud is a snapshot of the local map, with the people in it where they stood at that
  // moment. When a node is made, the scans of the stretch before it erase from the last
  // `clean_finished_nodes` finished nodes every point they saw through, as the local map does
  // scan by scan, and from the last `clean_moved_nodes` only the points seen moving
  // (observations 0: the motion filter's, or what a beam found moved in front of a known
  // surface). 0: off. Needs merger.free_space_reasoning. Care home, phantom cells of the map
  // clouds (3317 without free-space reasoning): 797 with neither, 347 with the last node cleaned,
  // 258 / 191 / 167 with the seen-moving points of 2 / 3 / 4 nodes. Cleaning every point of 2 or
  // 3 nodes cleans as much but takes wall points the later alignments use.
  int clean_finished_nodes = 1;
  int clean_moved_nodes = 3;
  // When a scan fits the local map neither from odometry's guess nor without the prior, it is
  // aligned again from guesses turned by +-1..failure_heading_steps x failure_heading_step_rad
  // (the best validated one is kept) before the tracker gives up: turning in place, odometry's
  // heading can be off by more than the projective alignment's basin, and a reset then leaves
  // the new local map with odometry's heading error for good. 0: off.
  int failure_heading_steps = 3;
  double failure_heading_step_rad = 0.15;
  // A turned alignment (no prior) whose position information is weaker than this ratio along
  // one axis (smallest / largest eigenvalue) is anywhere along a corridor: it is aligned again
  // holding odometry's position (the position part of the step's prior, heading free).
  double failure_heading_min_information_ratio = 0.005;

  template <class V>
  void Visit(V& v) {
    v("scan_matching", scan_matching);
    v("min_translation_m", min_translation_m);
    v("min_rotation_rad", min_rotation_rad);
    v("locate_skipped_scans", locate_skipped_scans);
    v("locate_min_correction_m", locate_min_correction_m);
    v("locate_min_correction_rad", locate_min_correction_rad);
    v("local_map_range_m", local_map_range_m);
    v("clip_every_m", clip_every_m);
    v("node_translation_m", node_translation_m);
    v("node_rotation_rad", node_rotation_rad);
    v("odometry_prior", odometry_prior);
    v("odometry_prior_robot_frame", odometry_prior_robot_frame);
    v("odometry_sigma_xy_m", odometry_sigma_xy_m);
    v("odometry_sigma_xy_per_m", odometry_sigma_xy_per_m);
    v("odometry_sigma_theta_rad", odometry_sigma_theta_rad);
    v("odometry_sigma_theta_per_rad", odometry_sigma_theta_per_rad);
    v("odometry_sigma_theta_per_m", odometry_sigma_theta_per_m);
    v("min_target_observations", min_target_observations);
    v("min_stable_target_fraction", min_stable_target_fraction);
    v("registration_covariance_scale", registration_covariance_scale);
    v("tight_odometry_edges", tight_odometry_edges);
    v("clean_finished_nodes", clean_finished_nodes);
    v("clean_moved_nodes", clean_moved_nodes);
    v("failure_heading_steps", failure_heading_steps);
    v("failure_heading_step_rad", failure_heading_step_rad);
    v("failure_heading_min_information_ratio", failure_heading_min_information_ratio);
  }
  void Validate(OptionErrors& e) const {
    e.Require(min_translation_m >= 0.0, "min_translation_m", "must be non-negative");
    e.Require(min_rotation_rad >= 0.0, "min_rotation_rad", "must be non-negative");
    e.Require(locate_min_correction_m >= 0.0, "locate_min_correction_m", "must be non-negative");
    e.Require(locate_min_correction_rad >= 0.0, "locate_min_correction_rad",
              "must be non-negative");
    e.Require(local_map_range_m > 0.0, "local_map_range_m", "must be positive");
    e.Require(clip_every_m > 0.0, "clip_every_m", "must be positive");
    e.Require(node_translation_m > 0.0, "node_translation_m", "must be positive");
    e.Require(node_rotation_rad > 0.0, "node_rotation_rad", "must be positive");
    e.Require(odometry_sigma_xy_m > 0.0, "odometry_sigma_xy_m", "must be positive");
    e.Require(odometry_sigma_theta_rad > 0.0, "odometry_sigma_theta_rad", "must be positive");
    e.Require(odometry_sigma_xy_per_m >= 0.0 && odometry_sigma_theta_per_rad >= 0.0 &&
                  odometry_sigma_theta_per_m >= 0.0,
              "odometry_sigma_xy_per_m", "odometry noise slopes must be non-negative");
    e.Require(min_target_observations >= 0, "min_target_observations", "must be non-negative");
    e.Require(min_stable_target_fraction >= 0.0 && min_stable_target_fraction <= 1.0,
              "min_stable_target_fraction", "must be in [0, 1]");
    e.Require(clean_finished_nodes >= 0, "clean_finished_nodes", "must be non-negative");
    e.Require(clean_moved_nodes >= 0, "clean_moved_nodes", "must be non-negative");
    e.Require(failure_heading_steps >= 0, "failure_heading_steps", "must be non-negative");
    e.Require(failure_heading_step_rad > 0.0 && failure_heading_step_rad < 1.0,
              "failure_heading_step_rad", "must be in (0, 1) rad");
    e.Require(
        failure_heading_min_information_ratio >= 0.0 && failure_heading_min_information_ratio < 1.0,
        "failure_heading_min_information_ratio", "must be in [0, 1)");
    e.Require(registration_covariance_scale > 0.0, "registration_covariance_scale",
              "must be positive");
  }
};

// How a new session attaches to a loaded map.
struct SessionOptions {
  // Uncertainty of the initial pose in the loaded map (the link from the nearest loaded node to
  // the session's first node, until loop closures tie the session in).
  double initial_pose_sigma_m = 0.5;
  double initial_pose_sigma_rad = 0.2;

  template <class V>
  void Visit(V& v) {
    v("initial_pose_sigma_m", initial_pose_sigma_m);
    v("initial_pose_sigma_rad", initial_pose_sigma_rad);
  }
  void Validate(OptionErrors& e) const {
    e.Require(initial_pose_sigma_m > 0.0, "initial_pose_sigma_m", "must be positive");
    e.Require(initial_pose_sigma_rad > 0.0, "initial_pose_sigma_rad", "must be positive");
  }
};

// Localization mode: the map is frozen and the robot is tracked against it. The tracker runs as in
// mapping; every every_m / every_rad its local map is aligned to the nearest map nodes' clouds
// and the map -> tracker correction follows the first alignment that validates.
struct LocalizationOptions {
  double every_m = 1.0;
  double every_rad = 0.5;
  int max_nodes = 3;              // map nodes tried, nearest first
  double search_radius_m = 8.0;   // ... within this distance of the robot
  double max_correction_m = 2.0;  // a larger jump is refused (a symmetric place, not the robot)

  template <class V>
  void Visit(V& v) {
    v("every_m", every_m);
    v("every_rad", every_rad);
    v("max_nodes", max_nodes);
    v("search_radius_m", search_radius_m);
    v("max_correction_m", max_correction_m);
  }
  void Validate(OptionErrors& e) const {
    e.Require(every_m > 0.0, "every_m", "must be positive");
    e.Require(every_rad > 0.0, "every_rad", "must be positive");
    e.Require(max_nodes >= 1, "max_nodes", "must be at least 1");
    e.Require(search_radius_m > 0.0, "search_radius_m", "must be positive");
    e.Require(max_correction_m > 0.0, "max_correction_m", "must be positive");
  }
};

}  // namespace longterm_mapper2d
