#include "longterm_mapper2d/core/evaluation/relation_metric.h"

#include <gtest/gtest.h>

#include <cmath>

namespace longterm_mapper2d {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

TEST(EvaluateRelations, HandComputedErrors) {
  // Stamps deliberately out of order: the evaluator sorts a copy.
  const std::vector<StampedPose2> trajectory = {{2.0, Pose2(1.0, 0.2, 0.1)},
                                                {1.0, Pose2(0.0, 0.0, 0.0)},
                                                {3.0, Pose2(5.0, 5.0, M_PI / 2)},
                                                {4.0, Pose2(5.0, 6.0, -3.1)}};
  const std::vector<Relation> relations = {
      // delta = (1, 0.2, 0.1), relation (1, 0, 0): epsilon = (0, 0.2, 0.1).
      {1.0, 2.0, Pose2(1.0, 0.0, 0.0)},
      // delta = (1, 0.2, 0.1) exactly: zero error.
      {1.0, 2.0, Pose2(1.0, 0.2, 0.1)},
      // pose(3) = (5, 5, pi/2), pose(4) = (5, 6, -3.1): delta = (1, 0, -3.1 - pi/2 wrapped).
      // relation (0, 1, 3.1 - pi/2): epsilon = R(-(3.1 - pi/2)) * ((1, 0) - (0, 1)), angle
      // wrap(-3.1 - pi/2 - 3.1 + pi/2) = wrap(-6.2) = 2 pi - 6.2.
      {3.0, 4.0, Pose2(0.0, 1.0, 3.1 - M_PI / 2)},
  };
  const auto result = EvaluateRelations(trajectory, relations);
  ASSERT_TRUE(result.ok()) << result.status().message();
  EXPECT_EQ(result->matched, 3);
  EXPECT_EQ(result->total, 3);
  ASSERT_EQ(result->errors.size(), 3u);
  EXPECT_NEAR(result->errors[0].trans_m, 0.2, 1e-12);
  EXPECT_NEAR(result->errors[0].rot_deg, 0.1 * kRadToDeg, 1e-10);
  EXPECT_NEAR(result->errors[1].trans_m, 0.0, 1e-12);
  EXPECT_NEAR(result->errors[1].rot_deg, 0.0, 1e-10);
  EXPECT_NEAR(result->errors[2].trans_m, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(result->errors[2].rot_deg, (2 * M_PI - 6.2) * kRadToDeg, 1e-9);

  const double t[] = {0.2, 0.0, std::sqrt(2.0)};
  const double mean = (t[0] + t[1] + t[2]) / 3;
  const double var =
      ((t[0] - mean) * (t[0] - mean) + mean * mean + (t[2] - mean) * (t[2] - mean)) / 3;
  EXPECT_NEAR(result->trans_abs_m.mean, mean, 1e-12);
  EXPECT_NEAR(result->trans_abs_m.std, std::sqrt(var), 1e-12);
  EXPECT_NEAR(result->trans_sq_m2.mean, (0.04 + 0.0 + 2.0) / 3, 1e-12);
  EXPECT_NEAR(result->trans_max_m, std::sqrt(2.0), 1e-12);
  const double r0 = 0.1 * kRadToDeg, r2 = (2 * M_PI - 6.2) * kRadToDeg;
  EXPECT_NEAR(result->rot_abs_deg.mean, (r0 + r2) / 3, 1e-9);
  EXPECT_NEAR(result->rot_sq_deg2.mean, (r0 * r0 + r2 * r2) / 3, 1e-8);
  EXPECT_NEAR(result->rot_max_deg, r0, 1e-9);
}

TEST(MeanStd, PopulationStatistics) {
  const MeanStd s = ComputeMeanStd({0.2, 0.4});
  EXPECT_NEAR(s.mean, 0.3, 1e-15);
  EXPECT_NEAR(s.std, 0.1, 1e-15);
  const MeanStd empty = ComputeMeanStd({});
  EXPECT_EQ(empty.mean, 0.0);
  EXPECT_EQ(empty.std, 0.0);
}

TEST(PoseAtStamp, ExactInterpolatedAndUnmatched) {
  const std::vector<StampedPose2> trajectory = {
      {0.0, Pose2(0.0, 0.0, 0.0)}, {0.1, Pose2(0.1, 0.0, 0.2)}, {1.1, Pose2(1.0, 1.0, 0.0)}};
  RelationMetricOptions options;
  // Exact match within 1e-6.
  auto pose = PoseAtStamp(trajectory, 0.1 + 5e-7, options);
  ASSERT_TRUE(pose.ok());
  EXPECT_DOUBLE_EQ(pose->x(), 0.1);
  // Interpolation between two poses 0.1 s apart.
  pose = PoseAtStamp(trajectory, 0.025, options);
  ASSERT_TRUE(pose.ok());
  EXPECT_NEAR(pose->x(), 0.025, 1e-12);
  EXPECT_NEAR(pose->theta(), 0.05, 1e-12);
  // In the 1 s gap: the neighbour on one side is too far.
  EXPECT_FALSE(PoseAtStamp(trajectory, 0.15, options).ok());
  EXPECT_FALSE(PoseAtStamp(trajectory, 1.05, options).ok());
  options.max_dt_s = 1.0;
  pose = PoseAtStamp(trajectory, 0.6, options);
  ASSERT_TRUE(pose.ok());
  EXPECT_NEAR(pose->x(), 0.55, 1e-12);
  // Outside the trajectory there is nothing to interpolate.
  EXPECT_FALSE(PoseAtStamp(trajectory, -0.01, options).ok());
  EXPECT_FALSE(PoseAtStamp(trajectory, 1.2, options).ok());
  EXPECT_FALSE(PoseAtStamp({}, 0.0, options).ok());
}

TEST(EvaluateRelations, UnmatchedRelationsAreCountedNotScored) {
  const std::vector<StampedPose2> trajectory = {
      {0.0, Pose2(0.0, 0.0, 0.0)}, {0.05, Pose2(0.5, 0.0, 0.0)}, {5.0, Pose2(3.0, 0.0, 0.0)}};
  const std::vector<Relation> relations = {
      {0.0, 0.025, Pose2(0.25, 0.0, 0.0)},  // interpolated, zero error
      {0.0, 2.0, Pose2(1.0, 0.0, 0.0)},     // 2.0 falls in a 4.95 s gap: unmatched
      {7.0, 0.0, Pose2(1.0, 0.0, 0.0)},     // after the end: unmatched
  };
  const auto result = EvaluateRelations(trajectory, relations);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->matched, 1);
  EXPECT_EQ(result->total, 3);
  EXPECT_TRUE(result->errors[0].matched);
  EXPECT_FALSE(result->errors[1].matched);
  EXPECT_FALSE(result->errors[2].matched);
  EXPECT_NEAR(result->trans_abs_m.mean, 0.0, 1e-12);
}

TEST(EvaluateRelations, RejectsNonFiniteInputAndBadOptions) {
  const std::vector<Relation> relations = {{0.0, 1.0, Pose2()}};
  EXPECT_FALSE(EvaluateRelations({{0.0, Pose2(NAN, 0, 0)}, {1.0, Pose2()}}, relations).ok());
  RelationMetricOptions bad;
  bad.max_dt_s = -1.0;
  EXPECT_FALSE(EvaluateRelations({{0.0, Pose2()}, {1.0, Pose2()}}, relations, bad).ok());
}

}  // namespace
}  // namespace longterm_mapper2d
