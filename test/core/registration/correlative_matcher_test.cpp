#include "longterm_mapper2d/core/registration/correlative_matcher.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace longterm_mapper2d {
namespace {

using Polyline = std::vector<Eigen::Vector2d>;

// Points every `spacing_m` along each polyline, starting `phase` (0..1) of a spacing in, with
// normals across the wall and optional Gaussian noise.
Cloud SampleWalls(const std::vector<Polyline>& walls, double spacing_m, double phase,
                  double noise_m = 0.0, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  Cloud cloud;
  for (const Polyline& wall : walls) {
    for (std::size_t s = 0; s + 1 < wall.size(); ++s) {
      const Eigen::Vector2d a = wall[s], b = wall[s + 1];
      const Eigen::Vector2d direction = (b - a).normalized();
      for (double t = phase * spacing_m; t < (b - a).norm(); t += spacing_m) {
        RichPoint p;
        p.point_m = a + t * direction + noise_m * Eigen::Vector2d(noise(rng), noise(rng));
        p.normal = Eigen::Vector2d(-direction.y(), direction.x());
        cloud.push_back(p);
      }
    }
  }
  return cloud;
}

// An 11.5 m x 7 m room with an alcove, a square pillar and a partial wall: no symmetry.
std::vector<Polyline> IrregularRoom() {
  return {{{-5.0, -3.5},
           {5.0, -3.5},
           {5.0, 0.5},
           {6.5, 0.5},
           {6.5, 2.5},
           {5.0, 2.5},
           {5.0, 3.5},
           {-5.0, 3.5},
           {-5.0, -3.5}},
          {{-2.0, -1.5}, {-1.5, -1.5}, {-1.5, -1.0}, {-2.0, -1.0}, {-2.0, -1.5}},
          {{1.0, 3.5}, {1.0, 1.5}}};
}

// A round room (radius 2.5 m, as a 48-gon) with a small pillar: nothing like IrregularRoom.
std::vector<Polyline> RoundRoom() {
  Polyline circle;
  for (int k = 0; k <= 48; ++k)
    circle.emplace_back(2.5 * std::cos(k * M_PI / 24), 2.5 * std::sin(k * M_PI / 24));
  return {circle, {{0.3, 0.3}, {0.6, 0.3}, {0.6, 0.6}, {0.3, 0.6}, {0.3, 0.3}}};
}

// The reference cloud seen from a frame at reference_T_current.
Cloud InFrame(const Pose2& reference_T_current, const Cloud& cloud_reference) {
  return Transform(reference_T_current.inverse(), cloud_reference);
}

TEST(CorrelativeMatcher, RecoversALargeOffsetFromIdentity) {
  const Pose2 truth(2.3, -1.7, 0.4);
  const Cloud reference = SampleWalls(IrregularRoom(), 0.03, 0.0);
  // A second sampling, with centimetre noise, in the current frame.
  const Cloud current = InFrame(truth, SampleWalls(IrregularRoom(), 0.03, 0.5, 0.01, 7));
  const CorrelativeMatcher matcher(reference, CorrelativeMatcherOptions{});
  const auto match = matcher.Match(current, Pose2(), 3.0, 0.6);
  ASSERT_TRUE(match.has_value());
  EXPECT_LT((match->reference_T_current.translation() - truth.translation()).norm(), 0.1);
  EXPECT_LT(std::abs(NormalizeAngle(match->reference_T_current.theta() - truth.theta())), 0.02);
  EXPECT_GT(match->score, 0.7);
  EXPECT_NEAR(match->score, matcher.Score(current, match->reference_T_current), 1e-6);
}

TEST(CorrelativeMatcher, RecoversAnOffsetFromAGuessElsewhere) {
  const Pose2 truth(-1.2, 0.8, -2.5);
  const Cloud reference = SampleWalls(IrregularRoom(), 0.03, 0.0);
  const Cloud current = InFrame(truth, SampleWalls(IrregularRoom(), 0.03, 0.3, 0.01, 3));
  const CorrelativeMatcher matcher(reference, CorrelativeMatcherOptions{});
  const Pose2 guess = Pose2(1.1, -0.9, 0.0) * truth * Pose2(0.0, 0.0, -0.35);
  const auto match = matcher.Match(current, guess, 2.0, 0.5);
  ASSERT_TRUE(match.has_value());
  EXPECT_LT((match->reference_T_current.translation() - truth.translation()).norm(), 0.1);
  EXPECT_LT(std::abs(NormalizeAngle(match->reference_T_current.theta() - truth.theta())), 0.02);
}

// The branch and bound must find the optimum of an exhaustive search of the same poses, for any
// number of levels, near the truth (a sharp peak) and away from it (a flat, low landscape).
TEST(CorrelativeMatcher, BranchAndBoundEqualsBruteForce) {
  const Pose2 truth(0.7, -0.4, 0.3);
  const Cloud reference = SampleWalls(IrregularRoom(), 0.03, 0.0);
  // Sparse enough not to be thinned, so that the exhaustive search stays quick.
  const Cloud current = InFrame(truth, SampleWalls(IrregularRoom(), 0.11, 0.5, 0.01, 5));
  const double linear_window_m = 0.5, angular_window_rad = 0.1;
  for (const Pose2& guess : {truth * Pose2(0.2, -0.15, 0.05), truth * Pose2(1.5, 1.0, 0.3)}) {
    for (int levels : {1, 3, 6}) {
      CorrelativeMatcherOptions options;
      options.levels = levels;
      options.max_points = 1000;
      options.min_score = 0.0;
      const CorrelativeMatcher matcher(reference, options);
      const CorrelativeSearchGrid grid =
          matcher.SearchGrid(current, linear_window_m, angular_window_rad);
      ASSERT_GT(grid.angular_steps, 0);
      double best = -1.0;
      for (int ia = -grid.angular_steps; ia <= grid.angular_steps; ++ia)
        for (int ix = -grid.linear_steps; ix <= grid.linear_steps; ++ix)
          for (int iy = -grid.linear_steps; iy <= grid.linear_steps; ++iy) {
            const Pose2 pose = Pose2(ix * grid.resolution_m, iy * grid.resolution_m, 0.0) * guess *
                               Pose2(0.0, 0.0, ia * grid.angular_step_rad);
            best = std::max(best, matcher.Score(current, pose));
          }
      const auto match = matcher.Match(current, guess, linear_window_m, angular_window_rad);
      ASSERT_TRUE(match.has_value()) << "levels " << levels;
      EXPECT_NEAR(match->score, best, 1e-6) << "levels " << levels;
      EXPECT_NEAR(matcher.Score(current, match->reference_T_current), match->score, 1e-6);
    }
  }
}

TEST(CorrelativeMatcher, RejectsACloudOfAnotherRoom) {
  const Cloud reference = SampleWalls(IrregularRoom(), 0.03, 0.0);
  const Cloud current = SampleWalls(RoundRoom(), 0.03, 0.0);
  const CorrelativeMatcher matcher(reference, CorrelativeMatcherOptions{});
  EXPECT_FALSE(matcher.Match(current, Pose2(), 3.0, 0.6).has_value());

  // What min_score cuts off: the best placement of the round room covers little of it.
  CorrelativeMatcherOptions accept_all;
  accept_all.min_score = 0.0;
  const auto best = CorrelativeMatcher(reference, accept_all).Match(current, Pose2(), 3.0, 0.6);
  ASSERT_TRUE(best.has_value());
  EXPECT_LT(best->score, 0.5);
}

TEST(CorrelativeMatcher, RejectsBadOptionsAndWindows) {
  const Cloud reference = SampleWalls(IrregularRoom(), 0.03, 0.0);
  auto with = [](auto change) {
    CorrelativeMatcherOptions options;
    change(options);
    return options;
  };
  const std::vector<CorrelativeMatcherOptions> bad = {
      with([](auto& o) { o.resolution_m = 0.0; }),   with([](auto& o) { o.resolution_m = -1; }),
      with([](auto& o) { o.kernel_sigma_m = 0.0; }), with([](auto& o) { o.levels = 0; }),
      with([](auto& o) { o.levels = 11; }),          with([](auto& o) { o.max_points = 0; }),
      with([](auto& o) { o.min_score = -0.1; }),     with([](auto& o) { o.min_score = 1.5; }),
      with([](auto& o) { o.resolution_m = NAN; }),
  };
  for (const CorrelativeMatcherOptions& options : bad)
    EXPECT_THROW({ CorrelativeMatcher m(reference, options); }, std::invalid_argument);

  const CorrelativeMatcher matcher(reference, CorrelativeMatcherOptions{});
  EXPECT_THROW(matcher.Match(reference, Pose2(), -1.0, 0.1), std::invalid_argument);
  EXPECT_THROW(matcher.Match(reference, Pose2(), 1.0, -0.1), std::invalid_argument);
  EXPECT_THROW(matcher.Match(reference, Pose2(), INFINITY, 0.1), std::invalid_argument);
}

TEST(CorrelativeMatcher, EmptyCloudsGiveNoMatch) {
  const Cloud room = SampleWalls(IrregularRoom(), 0.03, 0.0);
  CorrelativeMatcherOptions options;
  options.min_score = 0.0;
  const CorrelativeMatcher empty_reference(Cloud{}, options);
  EXPECT_FALSE(empty_reference.Match(room, Pose2(), 1.0, 0.2).has_value());
  EXPECT_EQ(empty_reference.Score(room, Pose2()), 0.0);

  const CorrelativeMatcher matcher(room, options);
  EXPECT_FALSE(matcher.Match(Cloud{}, Pose2(), 1.0, 0.2).has_value());
  EXPECT_EQ(matcher.Score(Cloud{}, Pose2()), 0.0);
  RichPoint not_finite;
  not_finite.point_m = Eigen::Vector2d(NAN, 1.0);
  EXPECT_FALSE(matcher.Match(Cloud{not_finite}, Pose2(), 1.0, 0.2).has_value());
}

// Points far outside the grid and a zero window are fine: a single pose is scored.
TEST(CorrelativeMatcher, ZeroWindowScoresTheGuessOnly) {
  const Cloud room = SampleWalls(IrregularRoom(), 0.03, 0.0);
  CorrelativeMatcherOptions options;
  options.min_score = 0.0;
  const CorrelativeMatcher matcher(room, options);
  const Pose2 guess(0.01, -0.02, 0.003);
  const auto match = matcher.Match(room, guess, 0.0, 0.0);
  ASSERT_TRUE(match.has_value());
  EXPECT_NEAR(match->reference_T_current.x(), guess.x(), 1e-12);
  EXPECT_NEAR(match->reference_T_current.theta(), guess.theta(), 1e-12);
  EXPECT_NEAR(match->score, matcher.Score(room, guess), 1e-6);
  EXPECT_EQ(matcher.Score(room, Pose2(1e9, -1e12, 0.0)), 0.0);
}

}  // namespace
}  // namespace longterm_mapper2d
