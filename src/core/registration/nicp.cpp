#include "longterm_mapper2d/core/registration/nicp.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "longterm_mapper2d/core/geometry/fast_atan2.h"
#include "longterm_mapper2d/core/registration/nearest_neighbour_grid.h"

namespace longterm_mapper2d {
namespace {

// One correspondence's contribution to the normal equations.
//
// With T = (R, t) mapping current into reference, q = R p_c + t and m = R n_c:
//   e = [q - p_r ; m - n_r]                          (point error, normal error)
//   Omega = blockdiag(Omega_p, w_n I),  Omega_p = w_perp n_r n_r' + w_tan (I - n_r n_r')
// so the point error counts mostly along the reference normal (point-to-line). With the left
// perturbation T <- exp(delta) T, delta = (dx, dy, dtheta):
//   de/ddelta = [[1, 0, -q_y], [0, 1, q_x], [0, 0, -m_y], [0, 0, m_x]].
// A pair with chi2 = e' Omega e above the cap c has Omega scaled by c / chi2, which caps its cost.
struct Accumulator {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  Eigen::Matrix3d H_prior = Eigen::Matrix3d::Zero();  // the prior's share of H
  double chi2 = 0.0;
  int outliers = 0;

  void Add(const Eigen::Vector2d& q, const Eigen::Vector2d& m, const RichPoint& ref,
           const RegistrationOptions& o) {
    const Eigen::Vector2d& n = ref.normal;
    const Eigen::Matrix2d nn = n * n.transpose();
    const Eigen::Matrix2d omega_p =
        o.normal_direction_information * nn +
        o.tangent_direction_information * (Eigen::Matrix2d::Identity() - nn);
    const double w_n = o.normal_error_information;
    const Eigen::Vector2d e_p = q - ref.point_m;
    const Eigen::Vector2d e_n = m - n;
    double pair_chi2 = e_p.dot(omega_p * e_p) + w_n * e_n.squaredNorm();
    double scale = 1.0;
    if (pair_chi2 > o.robust_chi2) {
      scale = o.robust_chi2 / pair_chi2;
      pair_chi2 = o.robust_chi2;
      ++outliers;
    }
    chi2 += pair_chi2;
    Eigen::Matrix<double, 2, 3> j_p;
    j_p << 1.0, 0.0, -q.y(), 0.0, 1.0, q.x();
    Eigen::Matrix<double, 2, 3> j_n;
    j_n << 0.0, 0.0, -m.y(), 0.0, 0.0, m.x();
    const Eigen::Matrix<double, 3, 2> jt_omega_p = j_p.transpose() * omega_p;
    H.noalias() += scale * (jt_omega_p * j_p + w_n * j_n.transpose() * j_n);
    b.noalias() += scale * (jt_omega_p * e_p + w_n * j_n.transpose() * e_n);
  }

  // Prior on T, in the reference frame: e_o = t2v(T * mean^-1); for the left perturbation,
  //   de_o/ddelta = [[1, 0, -e_y], [0, 1, e_x], [0, 0, 1]].
  // In the robot frame: E = mean^-1 * T, e_o = t2v(E). With exp(delta) T = T exp(Ad(T^-1) delta)
  // and t2v(E exp(eps)) = (t_E + R_E eps_t, theta_E + eps_theta),
  //   de_o/ddelta = blockdiag(R_E, 1) * Ad(T^-1),  Ad as in pose2.h.
  void AddPrior(const Pose2& T, const PosePrior& prior) {
    const Pose2 error = prior.robot_frame ? prior.reference_T_current.inverse() * T
                                          : T * prior.reference_T_current.inverse();
    const Eigen::Vector3d e = error.vector();
    Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
    if (prior.robot_frame) {
      j = ComposeJacobianRight(error, Pose2()) * Adjoint(T.inverse());  // blockdiag(R_E, 1) Ad
    } else {
      j(0, 2) = -e.y();
      j(1, 2) = e.x();
    }
    H_prior = j.transpose() * prior.information * j;
    H.noalias() += H_prior;
    b.noalias() += j.transpose() * prior.information * e;
    chi2 += e.dot(prior.information * e);
  }
};

}  // namespace

double PositionInformationRatio(const Eigen::Matrix3d& information) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(information.topLeftCorner<2, 2>(),
                                                             Eigen::EigenvaluesOnly);
  const Eigen::Vector2d lambda = eigen.eigenvalues();  // ascending
  // Not (> 0) rather than (<= 0): a NaN information has no position content either.
  if (!(lambda.y() > 0.0)) return 0.0;
  return lambda.x() / lambda.y();
}

template <class FindPairs>
RegistrationResult Nicp::Solve(const Cloud& reference, const Cloud& current, const Pose2& guess,
                               const std::optional<PosePrior>& prior, FindPairs&& find_pairs) {
  RegistrationResult result;
  Pose2 T = guess;
  const double cos_max_angle = std::cos(options_.max_normal_angle_rad);
  const double max_distance_sq =
      options_.max_correspondence_distance_m * options_.max_correspondence_distance_m;
  Accumulator last;
  for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
    const Eigen::Matrix2d R = T.rotation();
    const Eigen::Vector2d t = T.translation();
    find_pairs(T, cos_max_angle, max_distance_sq);
    Accumulator acc;
    for (const Pair& pair : pairs_) {
      const RichPoint& c = current[pair.current];
      acc.Add(R * c.point_m + t, R * c.normal, reference[pair.reference], options_);
    }
    if (prior) acc.AddPrior(T, *prior);
    result.iterations = iteration + 1;
    result.correspondences = static_cast<int>(pairs_.size());
    last = acc;
    if (pairs_.size() < 3 && !prior) break;  // no usable system: keep the estimate
    const Eigen::Matrix3d damped = acc.H + options_.damping * Eigen::Matrix3d::Identity();
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(damped);
    if (ldlt.info() != Eigen::Success) break;
    const Eigen::Vector3d delta = -ldlt.solve(acc.b);
    if (!delta.allFinite()) break;
    T = Pose2(delta.x(), delta.y(), delta.z()) * T;
    result.solved = true;
    if (delta.head<2>().norm() < options_.convergence_translation_m &&
        std::abs(delta.z()) < options_.convergence_rotation_rad) {
      break;
    }
  }
  result.reference_T_current = T;
  result.information = last.H;
  result.prior_information = last.H_prior;
  result.chi2 = last.chi2;
  result.outliers = last.outliers;
  return result;
}

RegistrationResult Nicp::AlignProjective(const Cloud& reference, const Cloud& current,
                                         const Pose2& guess, const Pose2& current_T_sensor,
                                         const ProjectorGeometry& geometry,
                                         const std::optional<PosePrior>& prior,
                                         ValidationView validation_view) {
  const Pose2 viewpoint = guess * current_T_sensor;  // in the reference frame
  const Pose2 viewpoint_T_reference = viewpoint.inverse();
  ProjectCloud(geometry, viewpoint_T_reference, reference, &reference_image_);
  const int seen_through =
      MarkSeenThrough(reference, current, guess, viewpoint_T_reference, geometry);
  const int window = options_.projective_window_bins;
  auto find_pairs = [&](const Pose2& T, double cos_max_angle, double max_distance_sq) {
    pairs_.clear();
    const Pose2 view_T_current = viewpoint_T_reference * T;
    const Eigen::Matrix2d R = T.rotation(), Rv = view_T_current.rotation();
    const Eigen::Vector2d t = T.translation(), tv = view_T_current.translation();
    for (int i = 0; i < static_cast<int>(current.size()); ++i) {
      const RichPoint& c = current[i];
      if (!c.has_normal()) continue;
      const Eigen::Vector2d in_view = Rv * c.point_m + tv;
      const int bin = geometry.BinOf(FastAtan2(in_view.y(), in_view.x()));
      if (bin < 0) continue;
      const Eigen::Vector2d q = R * c.point_m + t;
      const Eigen::Vector2d m = R * c.normal;
      int best = -1;
      double best_distance_sq = max_distance_sq;
      for (int offset = -window; offset <= window; ++offset) {
        const int b = geometry.Shift(bin, offset);
        if (b < 0) continue;
        const int j = reference_image_.indices[b];
        if (j < 0 || (seen_through > 0 && seen_through_[j])) continue;
        const RichPoint& r = reference[j];
        const double d2 = (q - r.point_m).squaredNorm();
        if (d2 < best_distance_sq && r.has_normal() && m.dot(r.normal) > cos_max_angle) {
          best = j;
          best_distance_sq = d2;
        }
      }
      if (best >= 0) pairs_.push_back({best, i});
    }
  };
  RegistrationResult result = Solve(reference, current, guess, prior, find_pairs);
  result.seen_through = seen_through;
  if (validation_view == ValidationView::kFromGuess) {
    // The reference image is already seen from there: only the current cloud is projected.
    result.validation = CompareWithReferenceImage(
        current, viewpoint_T_reference * result.reference_T_current, geometry);
  } else {
    result.validation = Validate(reference, current, result.reference_T_current,
                                 result.reference_T_current * current_T_sensor, geometry);
  }
  return result;
}

int Nicp::MarkSeenThrough(const Cloud& reference, const Cloud& current, const Pose2& guess,
                          const Pose2& viewpoint_T_reference, const ProjectorGeometry& geometry) {
  if (!(options_.see_through_margin_m > 0.0)) return 0;
  // Both clouds seen from the guessed sensor pose, bin by bin (the reference image is already
  // there). A reference surface facing the beam within the incidence limit, more than the margin
  // in front of the scan's return: the beam passed where it was. With a guess off by d, a
  // surface at incidence a moves by up to d / cos(a) along the beam, so the margin has to exceed
  // that (odometry over one processed step: about 2 cm on intel); at grazing incidence a bin
  // spans a long stretch of a wall and its range says nothing. Only points seen a few times:
  // a beam passing beside a chair leg thinner than a bin sees through it too, and a leg seen
  // by many scans has not moved (without the limit intel read 0.052 m instead of 0.025).
  ProjectCloud(geometry, viewpoint_T_reference * guess, current, &current_image_);
  seen_through_.assign(reference.size(), 0);
  const double min_cos = std::cos(options_.see_through_max_incidence_rad);
  const Eigen::Matrix2d R = viewpoint_T_reference.rotation();
  const Eigen::Vector2d t = viewpoint_T_reference.translation();
  int marked = 0;
  for (int bin = 0; bin < geometry.num_bins; ++bin) {
    const int j = reference_image_.indices[bin];
    if (j < 0 || current_image_.indices[bin] < 0) continue;
    if (!(reference_image_.ranges_m[bin] <
          current_image_.ranges_m[bin] - options_.see_through_margin_m)) {
      continue;
    }
    const RichPoint& r = reference[j];
    if (r.observations > options_.see_through_max_observations || !r.has_normal()) continue;
    const Eigen::Vector2d in_view = R * r.point_m + t;
    const double range = in_view.norm();
    if (!(range > 0.0) || -(R * r.normal).dot(in_view) < min_cos * range) continue;
    seen_through_[j] = 1;
    ++marked;
  }
  return marked;
}

RegistrationResult Nicp::AlignNearestNeighbour(const Cloud& reference, const Cloud& current,
                                               const Pose2& guess,
                                               const ProjectorGeometry& geometry,
                                               const std::optional<Pose2>& validation_viewpoint,
                                               const std::optional<PosePrior>& prior) {
  const NearestNeighbourGrid grid(reference, options_.max_correspondence_distance_m);
  RegistrationResult result = AlignNearestNeighbour(grid, reference, current, guess, prior);
  if (validation_viewpoint) {
    result.validation =
        Validate(reference, current, result.reference_T_current, *validation_viewpoint, geometry);
  }
  return result;
}

RegistrationResult Nicp::AlignNearestNeighbour(const NearestNeighbourGrid& grid,
                                               const Cloud& reference, const Cloud& current,
                                               const Pose2& guess,
                                               const std::optional<PosePrior>& prior) {
  auto find_pairs = [&](const Pose2& T, double cos_max_angle, double max_distance_sq) {
    pairs_.clear();
    const Eigen::Matrix2d R = T.rotation();
    const Eigen::Vector2d t = T.translation();
    for (int i = 0; i < static_cast<int>(current.size()); ++i) {
      const RichPoint& c = current[i];
      if (!c.has_normal()) continue;
      const int best =
          grid.Nearest(R * c.point_m + t, R * c.normal, cos_max_angle, max_distance_sq);
      if (best >= 0) pairs_.push_back({best, i});
    }
  };
  return Solve(reference, current, guess, prior, find_pairs);
}

RegistrationValidation Nicp::Validate(const Cloud& reference, const Cloud& current,
                                      const Pose2& reference_T_current, const Pose2& viewpoint,
                                      const ProjectorGeometry& geometry) {
  const Pose2 view_T_reference = viewpoint.inverse();
  ProjectCloud(geometry, view_T_reference, reference, &reference_image_);
  return CompareWithReferenceImage(current, view_T_reference * reference_T_current, geometry);
}

RegistrationValidation Nicp::CompareWithReferenceImage(const Cloud& current,
                                                       const Pose2& view_T_current,
                                                       const ProjectorGeometry& geometry) {
  RegistrationValidation v;
  ProjectCloud(geometry, view_T_current, current, &current_image_);
  for (int bin = 0; bin < geometry.num_bins; ++bin) {
    if (reference_image_.indices[bin] < 0 || current_image_.indices[bin] < 0) continue;
    ++v.correspondences;
    const double difference_m = current_image_.ranges_m[bin] - reference_image_.ranges_m[bin];
    if (std::abs(difference_m) < options_.inlier_distance_m) {
      ++v.inliers;
    } else if (difference_m < 0.0) {
      ++v.in_front;
    }
  }
  v.inlier_ratio = v.correspondences > 0 ? static_cast<double>(v.inliers) / v.correspondences : 0.0;
  v.correspondence_ratio =
      current.empty() ? 0.0 : static_cast<double>(v.correspondences) / current.size();
  v.accepted = v.correspondences >= options_.min_correspondences &&
               v.correspondence_ratio >= options_.min_correspondence_ratio &&
               v.inlier_ratio >= options_.min_inlier_ratio;
  return v;
}

}  // namespace longterm_mapper2d
