// LoopCloser's refusal of weak alignments that agree only in part (weak_information_ratio,
// weak_min_inlier_ratio): a slid corridor match is refused, a weak one that agrees is kept.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "longterm_mapper2d/core/loop_closing/loop_closer.h"
#include "testing/synthetic_scans.h"

namespace longterm_mapper2d {
namespace {

using test_support::CloudSeenFrom;

// A 2 m wide corridor along x whose y = 1 wall has a 1 m wide, `depth_m` deep door recess at
// each of `doors_x`: only the recesses' ends pin the corridor's length, weakly.
std::vector<Segment> CorridorWithDoors(const std::vector<double>& doors_x, double depth_m = 0.4) {
  std::vector<Segment> walls = {{Eigen::Vector2d(-20, -1), Eigen::Vector2d(20, -1)}};
  double x = -20.0;
  for (const double door_x : doors_x) {
    walls.push_back({Eigen::Vector2d(x, 1), Eigen::Vector2d(door_x, 1)});
    const double back_y = 1.0 + depth_m;
    walls.push_back({Eigen::Vector2d(door_x, 1), Eigen::Vector2d(door_x, back_y)});
    walls.push_back({Eigen::Vector2d(door_x, back_y), Eigen::Vector2d(door_x + 1, back_y)});
    walls.push_back({Eigen::Vector2d(door_x + 1, back_y), Eigen::Vector2d(door_x + 1, 1)});
    x = door_x + 1.0;
  }
  walls.push_back({Eigen::Vector2d(x, 1), Eigen::Vector2d(20, 1)});
  return walls;
}

TEST(LoopCloser, AWeakCorridorMatchThatAgreesOnlyInPartIsRefused) {
  // The old map: doors at x = -3 and 2. The new one, elsewhere along a corridor like it: one door
  // at -2.4 and a side room through an opening in the other wall. Laying the one door on the old
  // -3 slides the new map 0.6 m; the walls agree, the room does not (about half the new map).
  const Cloud old_map = CloudSeenFrom(CorridorWithDoors({-3.0, 2.0}), Pose2(), 8.0);
  auto elsewhere = CorridorWithDoors({-2.4});
  elsewhere[0] = {Eigen::Vector2d(-20, -1), Eigen::Vector2d(-1, -1)};
  elsewhere.push_back({Eigen::Vector2d(1.5, -1), Eigen::Vector2d(20, -1)});
  elsewhere.push_back({Eigen::Vector2d(-1, -1), Eigen::Vector2d(-1, -4)});
  elsewhere.push_back({Eigen::Vector2d(-1, -4), Eigen::Vector2d(1.5, -4)});
  elsewhere.push_back({Eigen::Vector2d(1.5, -4), Eigen::Vector2d(1.5, -1)});
  const Cloud new_map = CloudSeenFrom(elsewhere, Pose2(), 8.0);

  // Without the rule the slide validates and is not degenerate by min_information_ratio alone.
  LoopClosingOptions without_rule;
  without_rule.weak_min_inlier_ratio = 0.0;
  LoopCloser permissive(without_rule, RegistrationOptions{});
  const auto slid = permissive.AlignLocalMaps(old_map, new_map, {Pose2()});
  ASSERT_TRUE(slid.has_value());
  EXPECT_NEAR(std::abs(slid->x()), 0.6, 0.1);

  LoopCloser closer(LoopClosingOptions{}, RegistrationOptions{});
  EXPECT_FALSE(closer.AlignLocalMaps(old_map, new_map, {Pose2()}).has_value());
}

TEST(LoopCloser, AWeakCorridorMatchThatAgreesThroughoutIsKept) {
  // The same stretch seen twice, its recesses shallower (a few returns on their short side walls
  // pin the corridor's length, between min_information_ratio and weak_information_ratio): as weak
  // as above, but the whole new map agrees with the old one, so the closure stands.
  const auto corridor = CorridorWithDoors({-3.0, 2.0}, 0.37);
  const Cloud old_map = CloudSeenFrom(corridor, Pose2(), 8.0);
  const Cloud new_map = CloudSeenFrom(corridor, Pose2(), 8.0);
  const Pose2 guess(0.3, 0.05, 0.02);
  LoopCloser closer(LoopClosingOptions{}, RegistrationOptions{});
  const auto aligned = closer.AlignLocalMaps(old_map, new_map, {guess});
  ASSERT_TRUE(aligned.has_value());
  EXPECT_LT(aligned->translation().norm(), 0.02);
  EXPECT_LT(std::abs(aligned->theta()), 0.005);

  // It is weak: with the degeneracy threshold raised to weak_information_ratio it is refused.
  LoopClosingOptions strict;
  strict.min_information_ratio = strict.weak_information_ratio;
  LoopCloser strict_closer(strict, RegistrationOptions{});
  EXPECT_FALSE(strict_closer.AlignLocalMaps(old_map, new_map, {guess}).has_value());
}

}  // namespace
}  // namespace longterm_mapper2d
