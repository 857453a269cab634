// LoopCloser aligns merged local maps by their own points and validates with all of them
// (LoopClosingOptions::align_own_points): the points inherited from a merged-away map stand where
// the merge put them, errors included.
#include <gtest/gtest.h>

#include <cmath>

#include "longterm_mapper2d/core/loop_closing/loop_closer.h"
#include "testing/synthetic_scans.h"

namespace longterm_mapper2d {
namespace {

using test_support::CloudSeenFrom;

// An old local map of the irregular room: what its own scans saw from `a` (up to own_range_m), and
// what a map merged into it had seen from elsewhere (all of the room), placed by a merge whose
// relative pose was off by `merge_error`.
Cloud MergedOldMap(const Pose2& a, const Pose2& merge_error, double own_range_m = 5.0) {
  const auto room = test_support::IrregularRoom();
  Cloud cloud = CloudSeenFrom(room, a, own_range_m);
  const Pose2 map_T_elsewhere(3.0, 1.5, -0.4);
  const Cloud elsewhere = CloudSeenFrom(room, map_T_elsewhere, 20);
  for (RichPoint point : Transform(a.inverse() * map_T_elsewhere * merge_error, elsewhere)) {
    point.inherited = true;
    cloud.push_back(point);
  }
  return cloud;
}

struct AlignmentError {
  double translation_m = 0.0;
  double rotation_rad = 0.0;
};

AlignmentError AlignWith(const LoopClosingOptions& options, const Cloud& old_map,
                         const Pose2& old_T_new) {
  const auto room = test_support::IrregularRoom();
  const Cloud new_map = CloudSeenFrom(room, old_T_new, 20);
  LoopCloser closer(options, RegistrationOptions{});
  const auto aligned =
      closer.AlignLocalMaps(old_map, new_map, {old_T_new * Pose2(0.2, -0.1, 0.05)});
  EXPECT_TRUE(aligned.has_value());
  if (!aligned) return {1e9, 1e9};
  return {(aligned->translation() - old_T_new.translation()).norm(),
          std::abs(NormalizeAngle(aligned->theta() - old_T_new.theta()))};
}

TEST(LoopCloser, AMergedMapIsAlignedByItsOwnPoints) {
  const Pose2 old_T_new(1.2, 0.6, 0.5);
  const Cloud old_map = MergedOldMap(Pose2(), Pose2(0.04, -0.03, 0.015));

  const AlignmentError own = AlignWith(LoopClosingOptions{}, old_map, old_T_new);
  EXPECT_LT(own.translation_m, 0.005);
  EXPECT_LT(own.rotation_rad, 0.002);

  // By all its points, the misplaced inherited ones (most of the room) pull the closure off.
  LoopClosingOptions all_points;
  all_points.align_own_points = false;
  const AlignmentError all = AlignWith(all_points, old_map, old_T_new);
  EXPECT_GT(all.translation_m, 0.03);

  // Too few own points to stand alone: all of them, as above.
  LoopClosingOptions few_own = LoopClosingOptions{};
  few_own.own_points_min = static_cast<int>(old_map.size());
  const AlignmentError fallback = AlignWith(few_own, old_map, old_T_new);
  EXPECT_NEAR(fallback.translation_m, all.translation_m, 1e-9);
}

TEST(LoopCloser, AnAlignmentTheInheritedPointsContradictIsRefused) {
  // A merge that went wrong (the old map turned by 0.6 rad): the own points still align the new
  // map exactly, and alone they would validate it; all the points do not.
  const Pose2 old_T_new(1.2, 0.6, 0.5);
  const Cloud new_map = CloudSeenFrom(test_support::IrregularRoom(), old_T_new, 20);
  const Cloud old_map = MergedOldMap(Pose2(), Pose2(0.0, 0.0, 0.6), 4.5);
  Cloud own_only;
  for (const RichPoint& p : old_map) {
    if (!p.inherited) own_only.push_back(p);
  }
  LoopCloser closer(LoopClosingOptions{}, RegistrationOptions{});
  const Pose2 guess = old_T_new * Pose2(0.2, -0.1, 0.05);
  ASSERT_TRUE(closer.AlignLocalMaps(own_only, new_map, {guess}).has_value());
  EXPECT_FALSE(closer.AlignLocalMaps(old_map, new_map, {guess}).has_value());
}

TEST(LoopCloser, AMapWithoutInheritedPointsAlignsAsBefore) {
  const Pose2 old_T_new(1.2, 0.6, 0.5);
  const Cloud old_map = CloudSeenFrom(test_support::IrregularRoom(), Pose2(), 20);
  LoopClosingOptions all_points;
  all_points.align_own_points = false;
  EXPECT_DOUBLE_EQ(AlignWith(LoopClosingOptions{}, old_map, old_T_new).translation_m,
                   AlignWith(all_points, old_map, old_T_new).translation_m);
}

TEST(LoopCloser, AnOwnCorridorViewIsAlignedByAllThePoints) {
  // The old map's own scans saw 4 m of a corridor (nothing pins the alignment along it); the map
  // it took in saw the corridor's end 3 m on, placed right. The new map sees both.
  std::vector<Segment> corridor = test_support::Corridor();
  corridor.push_back(Segment{Eigen::Vector2d(3.0, -1.0), Eigen::Vector2d(3.0, 1.0)});
  Cloud old_map = CloudSeenFrom(test_support::Corridor(), Pose2(), 4.0);
  const Pose2 old_T_elsewhere(1.5, 0.2, 0.1);
  for (RichPoint point : Transform(old_T_elsewhere, CloudSeenFrom(corridor, old_T_elsewhere, 20))) {
    point.inherited = true;
    old_map.push_back(point);
  }
  const Pose2 old_T_new(0.8, -0.2, 0.3);
  const Cloud new_map = CloudSeenFrom(corridor, old_T_new, 20);
  const Pose2 guess = old_T_new * Pose2(0.2, -0.1, 0.05);

  LoopCloser closer(LoopClosingOptions{}, RegistrationOptions{});
  const auto aligned = closer.AlignLocalMaps(old_map, new_map, {guess});
  ASSERT_TRUE(aligned.has_value());
  EXPECT_LT((aligned->translation() - old_T_new.translation()).norm(), 0.01);
  EXPECT_LT(std::abs(NormalizeAngle(aligned->theta() - old_T_new.theta())), 0.005);

  LoopClosingOptions own_only;
  own_only.all_points_if_degenerate = false;
  LoopCloser refusing(own_only, RegistrationOptions{});
  EXPECT_FALSE(refusing.AlignLocalMaps(old_map, new_map, {guess}).has_value());
}

TEST(LoopCloser, OwnPointOptionsAreValidated) {
  LoopClosingOptions options;
  options.own_points_min = -1;
  OptionErrors errors;
  options.Validate(errors);
  EXPECT_NE(errors.ToString().find("own_points_min"), std::string::npos);
}

}  // namespace
}  // namespace longterm_mapper2d
