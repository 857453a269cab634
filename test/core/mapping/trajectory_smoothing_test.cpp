#include "longterm_mapper2d/core/mapping/trajectory_smoothing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

namespace longterm_mapper2d {
namespace {

// A robot driving a gentle arc, one scan every 0.2 s for 40 s, as the tracker saw it.
struct Drive {
  std::vector<double> stamps;
  std::vector<Pose2> tracker_T_base;
  Drive() {
    for (int i = 0; i < 200; ++i) {
      stamps.push_back(100.0 + 0.2 * i);
      tracker_T_base.push_back(Pose2(0.1 * i, 0.002 * i * i, 0.004 * i));
    }
  }
  // The scans in the map, each scan i through the correction (map_T_tracker) of its node.
  std::vector<Pose2> InMap(const std::vector<Pose2>& correction) const {
    std::vector<Pose2> poses;
    for (std::size_t i = 0; i < stamps.size(); ++i) {
      poses.push_back(correction[i] * tracker_T_base[i]);
    }
    return poses;
  }
};

double Distance(const Pose2& a, const Pose2& b) {
  return (a.translation() - b.translation()).norm();
}

TEST(TrajectorySmoothing, WhereTheNodesAgreeNothingChanges) {
  const Drive drive;
  const std::vector<Pose2> in_map =
      drive.InMap(std::vector<Pose2>(drive.stamps.size(), Pose2(12.0, -30.0, 2.5)));
  const auto smoothed = SmoothAcrossLocalMaps(drive.stamps, in_map, drive.tracker_T_base, 8.0);
  ASSERT_EQ(smoothed.size(), in_map.size());
  for (std::size_t i = 0; i < in_map.size(); ++i) {
    EXPECT_LT(Distance(smoothed[i], in_map[i]), 1e-9) << i;
    EXPECT_LT(std::abs(NormalizeAngle(smoothed[i].theta() - in_map[i].theta())), 1e-9) << i;
  }
}

TEST(TrajectorySmoothing, AJumpBetweenTwoNodesIsSpreadOverTheWindow) {
  // The second node (scans from 120 s) sits 0.3 m and 0.05 rad off the first in the graph: the
  // trajectory as the nodes give it jumps there; smoothed, no step between scans exceeds what
  // the window spreads, and scans farther than the window from the boundary are untouched.
  const Drive drive;
  std::vector<Pose2> correction(drive.stamps.size(), Pose2(1.0, 2.0, 0.3));
  for (std::size_t i = 100; i < correction.size(); ++i) {
    correction[i] = Pose2(0.3, 0.0, 0.05) * correction[i];
  }
  const std::vector<Pose2> in_map = drive.InMap(correction);
  const auto smoothed = SmoothAcrossLocalMaps(drive.stamps, in_map, drive.tracker_T_base, 4.0);
  const double jump = Distance(
      in_map[100], in_map[99] * drive.tracker_T_base[99].Between(drive.tracker_T_base[100]));
  ASSERT_GT(jump, 0.3);
  double largest_step_error = 0.0;
  for (std::size_t i = 1; i < smoothed.size(); ++i) {
    const Pose2 expected =
        smoothed[i - 1] * drive.tracker_T_base[i - 1].Between(drive.tracker_T_base[i]);
    largest_step_error = std::max(largest_step_error, Distance(smoothed[i], expected));
  }
  EXPECT_LT(largest_step_error, 0.05 * jump);  // 40 scans in a 8 s window share the jump
  for (std::size_t i : {0u, 50u, 79u, 121u, 150u, 199u}) {  // over 4 s from 120 s
    EXPECT_LT(Distance(smoothed[i], in_map[i]), 1e-9) << i;
  }
  // Halfway through the window the scan sits between what the two nodes give it.
  const Pose2 first = correction[0] * drive.tracker_T_base[100];
  const Pose2 second = correction[100] * drive.tracker_T_base[100];
  EXPECT_LT(Distance(smoothed[100], first), Distance(second, first));
  EXPECT_LT(Distance(smoothed[100], second), Distance(second, first));
}

TEST(TrajectorySmoothing, AZeroWindowKeepsEachScansOwnNode) {
  const Drive drive;
  std::vector<Pose2> correction(drive.stamps.size(), Pose2());
  for (std::size_t i = 100; i < correction.size(); ++i) correction[i] = Pose2(0.3, 0.0, 0.05);
  const std::vector<Pose2> in_map = drive.InMap(correction);
  const auto smoothed = SmoothAcrossLocalMaps(drive.stamps, in_map, drive.tracker_T_base, 0.0);
  for (std::size_t i = 0; i < in_map.size(); ++i) {
    EXPECT_EQ(smoothed[i].x(), in_map[i].x());
    EXPECT_EQ(smoothed[i].theta(), in_map[i].theta());
  }
}

TEST(TrajectoryCorrections, ScansWithoutACorrectionInTheirWindowAreUntouched) {
  const Drive drive;
  const std::vector<Pose2> in_map = drive.InMap(std::vector<Pose2>(drive.stamps.size()));
  std::vector<std::optional<Pose2>> corrections(drive.stamps.size());
  corrections[100] = Pose2(0.02, -0.01, 0.003);  // at 120 s
  const auto corrected = AverageCorrections(drive.stamps, corrections, in_map, 1.9);
  for (std::size_t i = 0; i < in_map.size(); ++i) {
    const Pose2 expected = (i >= 91 && i <= 109) ? *corrections[100] * in_map[i] : in_map[i];
    EXPECT_LT(Distance(corrected[i], expected), 1e-9) << i;
    EXPECT_LT(std::abs(NormalizeAngle(corrected[i].theta() - expected.theta())), 1e-12) << i;
  }
}

TEST(TrajectoryCorrections, AScanTakesTheMeanOfTheCorrectionsAroundIt) {
  // Two corrections 1 s apart, far from the map origin (the sums are relative to the first):
  // between them each scan takes their mean, past them only the nearer one.
  const Drive drive;
  const std::vector<Pose2> in_map =
      drive.InMap(std::vector<Pose2>(drive.stamps.size(), Pose2(5000.0, -3000.0, 1.0)));
  std::vector<std::optional<Pose2>> corrections(drive.stamps.size());
  const Pose2 a(0.04, 0.0, 0.01), b(0.0, 0.02, -0.01);
  // As map-frame corrections about each scan's own position: C = T * local * T^-1.
  corrections[100] = in_map[100] * a * in_map[100].inverse();
  corrections[105] = in_map[105] * b * in_map[105].inverse();
  const auto corrected = AverageCorrections(drive.stamps, corrections, in_map, 1.0);
  const Pose2 only_a = *corrections[100] * in_map[96];
  EXPECT_LT(Distance(corrected[96], only_a), 1e-6);  // 0.8 s before the first: only it
  const Pose2 with_a = *corrections[100] * in_map[102], with_b = *corrections[105] * in_map[102];
  const Eigen::Vector2d mean = 0.5 * (with_a.translation() + with_b.translation());
  EXPECT_LT((corrected[102].translation() - mean).norm(), 1e-6);
  EXPECT_NEAR(NormalizeAngle(corrected[102].theta() - in_map[102].theta()), 0.0, 1e-9);
}

TEST(TrajectoryCorrections, CorrectionsStayWithinTheirStretch) {
  const Drive drive;
  const std::vector<Pose2> in_map = drive.InMap(std::vector<Pose2>(drive.stamps.size()));
  std::vector<bool> in_stretch(drive.stamps.size(), true);
  in_stretch[100] = false;  // e.g. a scan recorded in localization: ends a stretch
  std::vector<std::optional<Pose2>> corrections(drive.stamps.size());
  corrections[99] = Pose2(0.05, 0.0, 0.0);
  std::vector<Pose2> corrected = in_map;
  CorrectStretches(drive.stamps, in_stretch, corrections, 4.0, corrected);
  EXPECT_LT(Distance(corrected[98], *corrections[99] * in_map[98]), 1e-9);
  for (std::size_t i = 100; i < 110; ++i) EXPECT_LT(Distance(corrected[i], in_map[i]), 1e-12) << i;
}

}  // namespace
}  // namespace longterm_mapper2d
