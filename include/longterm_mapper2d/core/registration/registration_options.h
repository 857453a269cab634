#pragma once

#include <cmath>

#include "longterm_mapper2d/core/config/option_errors.h"

namespace longterm_mapper2d {

// NICP registration: correspondences, error weights, solver and validation.
struct RegistrationOptions {
  int max_iterations = 30;
  // Levenberg-style damping added to the normal equations (lambda I).
  double damping = 1.0;
  // Correspondence gates.
  double max_correspondence_distance_m = 0.3;
  double max_normal_angle_rad = M_PI / 6.0;
  // Projective search: bins i-w .. i+w around a point's own bin i.
  int projective_window_bins = 3;
  // Per-point information in the reference normal's frame: along the normal (point-to-line),
  // along the tangent (a little, so a straight corridor is not singular), and on the normal error.
  double normal_direction_information = 100.0;
  double tangent_direction_information = 1e-3;
  double normal_error_information = 1.0;
  // Projective alignment (tracking): a reference point seen by at most
  // see_through_max_observations scans that the scan sees through from the guessed pose (in its
  // bin the scan's return lies more than see_through_margin_m behind it, the point facing the
  // beam within see_through_max_incidence_rad) is no partner for this alignment: it moved since,
  // as a person who stood and walks on. 0: off.
  double see_through_margin_m = 0.0;
  double see_through_max_incidence_rad = M_PI / 3.0;
  int see_through_max_observations = 3;
  // Robust cap: a pair with chi2 = e' Omega e above this is down-weighted to this cost.
  double robust_chi2 = 1.0;
  // Stop when a step moves less than this.
  double convergence_translation_m = 1e-5;
  double convergence_rotation_rad = 1e-6;
  // Validation (ranges compared bin by bin from the estimated viewpoint).
  double inlier_distance_m = 0.3;
  double min_inlier_ratio = 0.6;
  double min_correspondence_ratio = 0.3;
  int min_correspondences = 20;

  template <class V>
  void Visit(V& v) {
    v("max_iterations", max_iterations);
    v("damping", damping);
    v("max_correspondence_distance_m", max_correspondence_distance_m);
    v("max_normal_angle_rad", max_normal_angle_rad);
    v("projective_window_bins", projective_window_bins);
    v("normal_direction_information", normal_direction_information);
    v("tangent_direction_information", tangent_direction_information);
    v("normal_error_information", normal_error_information);
    v("see_through_margin_m", see_through_margin_m);
    v("see_through_max_incidence_rad", see_through_max_incidence_rad);
    v("see_through_max_observations", see_through_max_observations);
    v("robust_chi2", robust_chi2);
    v("convergence_translation_m", convergence_translation_m);
    v("convergence_rotation_rad", convergence_rotation_rad);
    v("inlier_distance_m", inlier_distance_m);
    v("min_inlier_ratio", min_inlier_ratio);
    v("min_correspondence_ratio", min_correspondence_ratio);
    v("min_correspondences", min_correspondences);
  }
  void Validate(OptionErrors& e) const {
    e.Require(max_iterations >= 1, "max_iterations", "must be at least 1");
    e.Require(damping >= 0.0, "damping", "must be non-negative");
    e.Require(max_correspondence_distance_m > 0.0, "max_correspondence_distance_m",
              "must be positive");
    e.Require(max_normal_angle_rad > 0.0 && max_normal_angle_rad <= M_PI, "max_normal_angle_rad",
              "must be in (0, pi]");
    e.Require(projective_window_bins >= 0, "projective_window_bins", "must be non-negative");
    e.Require(normal_direction_information > 0.0, "normal_direction_information",
              "must be positive");
    e.Require(tangent_direction_information >= 0.0, "tangent_direction_information",
              "must be non-negative");
    e.Require(normal_error_information >= 0.0, "normal_error_information", "must be non-negative");
    e.Require(see_through_margin_m >= 0.0, "see_through_margin_m", "must be non-negative");
    e.Require(see_through_max_incidence_rad > 0.0 && see_through_max_incidence_rad <= M_PI / 2.0,
              "see_through_max_incidence_rad", "must be in (0, pi/2]");
    e.Require(see_through_max_observations >= 0, "see_through_max_observations",
              "must be non-negative");
    e.Require(robust_chi2 > 0.0, "robust_chi2", "must be positive");
    e.Require(inlier_distance_m > 0.0, "inlier_distance_m", "must be positive");
    e.Require(min_inlier_ratio >= 0.0 && min_inlier_ratio <= 1.0, "min_inlier_ratio",
              "must be in [0, 1]");
    e.Require(min_correspondence_ratio >= 0.0 && min_correspondence_ratio <= 1.0,
              "min_correspondence_ratio", "must be in [0, 1]");
    e.Require(min_correspondences >= 3, "min_correspondences", "must be at least 3");
  }
};

}  // namespace longterm_mapper2d
