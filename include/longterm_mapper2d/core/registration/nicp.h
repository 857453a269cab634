#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/cloud/range_projector.h"
#include "longterm_mapper2d/core/cloud/rich_point.h"
#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/registration/nearest_neighbour_grid.h"
#include "longterm_mapper2d/core/registration/registration_options.h"

namespace longterm_mapper2d {

// A Gaussian belief on reference_T_current (e.g. from odometry). The information matrix is for the
// error t2v(T * mean^-1), translation expressed in the reference frame, or with robot_frame for
// t2v(mean^-1 * T), in the current frame. The two agree to first order; the first has a second
// order term |t| dtheta^2 / 2 that grows with the distance t of the mean from the reference
// frame's origin (an odometry frame hundreds of metres away bends every turn towards the prior's).
struct PosePrior {
  Pose2 reference_T_current;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  bool robot_frame = false;
};

struct RegistrationValidation {
  int correspondences = 0;  // bins where both clouds have a facing point
  int inliers = 0;          // ... whose ranges agree within inlier_distance_m
  // ... where the current cloud is nearer by more than that: it has a surface in front of what
  // the reference sees there (the rest of the disagreeing bins have it hidden behind).
  int in_front = 0;
  double inlier_ratio = 0.0;
  double correspondence_ratio = 0.0;  // correspondences / current points
  bool accepted = false;
};

struct RegistrationResult {
  Pose2 reference_T_current;
  // Information (inverse covariance) of the estimate: the Gauss-Newton Hessian of the last
  // iteration, prior included, without damping.
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  // The prior's share of `information` (zero without a prior): information - prior_information
  // is what the scan alone says.
  Eigen::Matrix3d prior_information = Eigen::Matrix3d::Zero();
  int iterations = 0;
  int correspondences = 0;
  int outliers = 0;  // pairs capped by the robust kernel in the last iteration
  double chi2 = 0.0;
  bool solved = false;   // false: no usable system (no pairs and no prior)
  int seen_through = 0;  // reference points left out: the scan saw through them (projective)
  RegistrationValidation validation;
};

// How well an estimate's position is pinned along its weakest direction against its strongest:
// smallest over largest eigenvalue of the position block of `information` (1: as well in every
// direction; near 0: a corridor, free along it). 0 for an information without position content.
double PositionInformationRatio(const Eigen::Matrix3d& information);

// NICP for 2D clouds with normals (Serafin & Grisetti): point-to-line plus normal error, damped
// Gauss-Newton with a robust cap and an optional prior. Reuses its buffers between calls.
class Nicp {
 public:
  explicit Nicp(const RegistrationOptions& options) : options_(options) {}

  // Projective association: the reference is projected once from the guessed sensor pose
  // (guess * current_T_sensor) into `geometry` bins; each current point looks for its partner in
  // the bins around its own. For scan-to-local-map tracking.
  // Where the validation looks from: the estimated sensor pose (kFromResult), or the guessed one
  // (kFromGuess), which saves projecting the reference again; for a guess close to the result.
  enum class ValidationView { kFromResult, kFromGuess };
  RegistrationResult AlignProjective(const Cloud& reference, const Cloud& current,
                                     const Pose2& guess, const Pose2& current_T_sensor,
                                     const ProjectorGeometry& geometry,
                                     const std::optional<PosePrior>& prior,
                                     ValidationView validation_view = ValidationView::kFromResult);

  // Nearest-neighbour association through a grid over the reference (NearestNeighbourGrid): for
  // map-to-map alignment (local maps of loop closures and merges), where there is no single
  // viewpoint.
  // Validation projects both clouds from `validation_viewpoint` (in the reference frame); without
  // one the result is not validated (`validation` stays default: not accepted), for a caller that
  // validates otherwise or only wants the pose.
  RegistrationResult AlignNearestNeighbour(const Cloud& reference, const Cloud& current,
                                           const Pose2& guess, const ProjectorGeometry& geometry,
                                           const std::optional<Pose2>& validation_viewpoint,
                                           const std::optional<PosePrior>& prior);

  // The same over a grid built once for many alignments with one reference (`grid` built over
  // `reference` with a radius of at least max_correspondence_distance_m); not validated.
  RegistrationResult AlignNearestNeighbour(const NearestNeighbourGrid& grid, const Cloud& reference,
                                           const Cloud& current, const Pose2& guess,
                                           const std::optional<PosePrior>& prior);
  // The validation of §3.4: both clouds seen from `viewpoint` (reference frame), bin by bin.
  RegistrationValidation Validate(const Cloud& reference, const Cloud& current,
                                  const Pose2& reference_T_current, const Pose2& viewpoint,
                                  const ProjectorGeometry& geometry);

  const RegistrationOptions& options() const { return options_; }

 private:
  // Validate() against the reference image as last projected (from the view of view_T_current).
  RegistrationValidation CompareWithReferenceImage(const Cloud& current,
                                                   const Pose2& view_T_current,
                                                   const ProjectorGeometry& geometry);

  // RegistrationOptions::see_through_margin_m: marks in seen_through_ the reference points the
  // current cloud, placed at `guess`, sees through (reference_image_ must be the reference seen
  // from the guessed sensor pose); returns how many.
  int MarkSeenThrough(const Cloud& reference, const Cloud& current, const Pose2& guess,
                      const Pose2& viewpoint_T_reference, const ProjectorGeometry& geometry);

  struct Pair {
    int reference;
    int current;
  };
  template <class FindPairs>
  RegistrationResult Solve(const Cloud& reference, const Cloud& current, const Pose2& guess,
                           const std::optional<PosePrior>& prior, FindPairs&& find_pairs);

  RegistrationOptions options_;
  RangeImage reference_image_;
  RangeImage current_image_;
  std::vector<Pair> pairs_;
  std::vector<char> seen_through_;  // per reference point (AlignProjective)
  Cloud current_in_reference_;
};

}  // namespace longterm_mapper2d
