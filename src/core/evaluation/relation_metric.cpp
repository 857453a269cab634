#include "longterm_mapper2d/core/evaluation/relation_metric.h"

#include <algorithm>
#include <cmath>

namespace longterm_mapper2d {

MeanStd ComputeMeanStd(const std::vector<double>& values) {
  MeanStd result;
  if (values.empty()) return result;
  double sum = 0.0;
  for (const double v : values) sum += v;
  result.mean = sum / values.size();
  // Two-pass variance: the squared errors span many orders of magnitude.
  double sum_sq = 0.0;
  for (const double v : values) sum_sq += (v - result.mean) * (v - result.mean);
  result.std = std::sqrt(sum_sq / values.size());
  return result;
}

StatusOr<Pose2> PoseAtStamp(const std::vector<StampedPose2>& sorted_trajectory, double stamp_s,
                            const RelationMetricOptions& options) {
  if (sorted_trajectory.empty()) return Status::Error("empty trajectory");
  const auto after =
      std::lower_bound(sorted_trajectory.begin(), sorted_trajectory.end(), stamp_s,
                       [](const StampedPose2& p, double t) { return p.stamp_s < t; });
  // Exact match: the nearest of the two neighbours of the insertion point.
  const StampedPose2* nearest = nullptr;
  if (after != sorted_trajectory.end()) nearest = &*after;
  if (after != sorted_trajectory.begin()) {
    const StampedPose2* before = &*(after - 1);
    if (nearest == nullptr ||
        std::abs(before->stamp_s - stamp_s) < std::abs(nearest->stamp_s - stamp_s)) {
      nearest = before;
    }
  }
  if (std::abs(nearest->stamp_s - stamp_s) <= options.exact_match_s) return nearest->pose;

  if (after == sorted_trajectory.begin() || after == sorted_trajectory.end()) {
    return Status::Error("stamp outside the trajectory");
  }
  const StampedPose2& a = *(after - 1);
  const StampedPose2& b = *after;
  if (stamp_s - a.stamp_s > options.max_dt_s || b.stamp_s - stamp_s > options.max_dt_s) {
    return Status::Error("no trajectory poses within max_dt_s on both sides");
  }
  const double fraction = (stamp_s - a.stamp_s) / (b.stamp_s - a.stamp_s);
  return Interpolate(a.pose, b.pose, fraction);
}

StatusOr<RelationMetricResult> EvaluateRelations(const std::vector<StampedPose2>& trajectory,
                                                 const std::vector<Relation>& relations,
                                                 const RelationMetricOptions& options) {
  OptionErrors option_errors;
  options.Validate(option_errors);
  if (!option_errors.empty()) return Status::Error(option_errors.ToString());
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    if (!std::isfinite(trajectory[i].stamp_s) || !trajectory[i].pose.IsFinite()) {
      return Status::Error("trajectory pose " + std::to_string(i) + " is not finite");
    }
  }
  std::vector<StampedPose2> sorted = trajectory;
  std::stable_sort(sorted.begin(), sorted.end(), [](const StampedPose2& a, const StampedPose2& b) {
    return a.stamp_s < b.stamp_s;
  });

  RelationMetricResult result;
  result.total = static_cast<int>(relations.size());
  std::vector<double> trans_abs, trans_sq, rot_abs, rot_sq;
  for (const Relation& relation : relations) {
    RelationError error;
    error.t1_s = relation.t1_s;
    error.t2_s = relation.t2_s;
    const StatusOr<Pose2> pose1 = PoseAtStamp(sorted, relation.t1_s, options);
    const StatusOr<Pose2> pose2 = PoseAtStamp(sorted, relation.t2_s, options);
    if (pose1.ok() && pose2.ok()) {
      const Pose2 estimated_t1_T_t2 = pose1->Between(*pose2);
      const Pose2 epsilon = relation.t1_T_t2.inverse() * estimated_t1_T_t2;
      error.matched = true;
      error.trans_m = epsilon.translation().norm();
      error.rot_deg = std::abs(NormalizeAngle(epsilon.theta())) * 180.0 / M_PI;
      trans_abs.push_back(error.trans_m);
      trans_sq.push_back(error.trans_m * error.trans_m);
      rot_abs.push_back(error.rot_deg);
      rot_sq.push_back(error.rot_deg * error.rot_deg);
      result.trans_max_m = std::max(result.trans_max_m, error.trans_m);
      result.rot_max_deg = std::max(result.rot_max_deg, error.rot_deg);
      ++result.matched;
    }
    result.errors.push_back(error);
  }
  result.trans_abs_m = ComputeMeanStd(trans_abs);
  result.trans_sq_m2 = ComputeMeanStd(trans_sq);
  result.rot_abs_deg = ComputeMeanStd(rot_abs);
  result.rot_sq_deg2 = ComputeMeanStd(rot_sq);
  return result;
}

}  // namespace longterm_mapper2d
