// The care home patrol (config/worlds/care_home.yaml) mapped with the lasers of other robots: a
// 180 degree laser of 181 beams that interlaces its sweeps (every other scan starts half a beam
// later), a 180 degree laser of 361 beams, and a 270 degree laser 0.22 m ahead of the base. One
// configuration (the default) for all of them: the scan geometry comes from each scan, the mount
// from base_T_laser.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/mapping/mapper.h"
#include "longterm_mapper2d/core/simulation/session_simulator.h"
#include "testing/simulated_mapping.h"

namespace longterm_mapper2d {
namespace {

struct LaserCase {
  const char* name;
  int beams;
  double fov_deg;
  double laser_x_m;
  bool interlaced;
  int seed = 11;
  // Bounds on the errors in the frame of the first scan (see the measured figures below).
  double max_rmse_m = 0.15;
  double max_error_m = 0.4;
};

// Test names and failure messages show the laser, not the struct's bytes.
void PrintTo(const LaserCase& c, std::ostream* os) { *os << c.name; }

std::uint64_t Counter(const Mapper& mapper, const std::string& name) {
  const auto it = mapper.stats().counters.find(name);
  return it == mapper.stats().counters.end() ? 0 : it->second;
}

// RMSE of the positions after the rigid motion that best aligns them with the truth: the map's
// own shape, whatever its frame.
double RigidlyAlignedRmse(const std::vector<StampedPose2>& trajectory,
                          const std::vector<SimulatedStep>& steps) {
  const std::size_t n = std::min(trajectory.size(), steps.size());
  Eigen::Vector2d mean_estimate = Eigen::Vector2d::Zero(), mean_truth = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    mean_estimate += trajectory[i].pose.translation() / n;
    mean_truth += steps[i].map_T_base.translation() / n;
  }
  Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    h += (trajectory[i].pose.translation() - mean_estimate) *
         (steps[i].map_T_base.translation() - mean_truth).transpose();
  }
  const double angle = std::atan2(h(0, 1) - h(1, 0), h(0, 0) + h(1, 1));
  const Eigen::Matrix2d r = Eigen::Rotation2Dd(angle).toRotationMatrix();
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d e = r * (trajectory[i].pose.translation() - mean_estimate) -
                              (steps[i].map_T_base.translation() - mean_truth);
    sum_sq += e.squaredNorm();
  }
  return std::sqrt(sum_sq / n);
}

class OtherLasers : public ::testing::TestWithParam<LaserCase> {};

TEST_P(OtherLasers, ThePatrolIsTrackedAndItsLoopsClosed) {
  const LaserCase& laser = GetParam();
  const auto world = LoadWorld(std::string(LTM_CONFIG_DIR) + "/worlds/care_home.yaml");
  ASSERT_TRUE(world.ok()) << world.status().message();
  SimulationOptions simulation;
  simulation.duration_s = 430.0;  // one whole patrol: back to the start, loops on the way
  simulation.beams = laser.beams;
  simulation.fov_rad = laser.fov_deg * M_PI / 180.0;
  simulation.laser_x_m = laser.laser_x_m;
  simulation.interlaced = laser.interlaced;
  SessionSimulator simulator(*world, 1, simulation, laser.seed);
  const auto steps = simulator.Run();
  ASSERT_GT(steps.size(), 2u);
  if (laser.interlaced) {
    ASSERT_NE(steps[0].scan.angle_min_rad, steps[1].scan.angle_min_rad);
  }
  Mapper mapper(MapperOptions{});
  test_support::MapSimulatedSteps(steps, simulator.base_T_laser(), mapper);
  const std::vector<double> errors = test_support::PositionErrors(mapper, steps);
  ASSERT_EQ(errors.size(), steps.size());
  double sum_sq = 0.0, max_m = 0.0;
  for (const double e : errors) {
    sum_sq += e * e;
    max_m = std::max(max_m, e);
  }
  const double rmse_m = std::sqrt(sum_sq / errors.size());
  const double aligned_rmse_m = RigidlyAlignedRmse(mapper.Trajectory(), steps);
  std::printf(
      "%s: trajectory RMSE %.3f m (rigidly aligned %.3f m), max %.3f m, %llu tracker failures, "
      "%llu closures\n",
      laser.name, rmse_m, aligned_rmse_m, max_m,
      static_cast<unsigned long long>(Counter(mapper, "tracker_failures")),
      static_cast<unsigned long long>(Counter(mapper, "loop_closures_accepted")));
  // Measured (2026-12-04): rigidly aligned 0.009 / 0.034 / 0.016 / 0.017 m for the four lasers,
  // 0.010-0.035 m for other beam counts and mounts (0 to 0.3 m ahead, 0.2 m behind). Unaligned,
  // the map's frame is where the first scan was, and the start's own small heading error turns
  // it: 0.011-0.120 m. No tracker failure here (one with 361 beams 0.1 m ahead).
  EXPECT_LE(Counter(mapper, "tracker_failures"), 1u);
  EXPECT_GT(Counter(mapper, "loop_closures_accepted"), 0u);
  EXPECT_LT(aligned_rmse_m, 0.06);
  EXPECT_LT(rmse_m, laser.max_rmse_m);
  EXPECT_LT(max_m, laser.max_error_m);
}

INSTANTIATE_TEST_SUITE_P(
    CareHome, OtherLasers,
    ::testing::Values(LaserCase{"default_271_beams_270_deg", 271, 270.0, 0.1, false},
                      LaserCase{"interlaced_181_beams_180_deg", 181, 180.0, 0.0, true},
                      LaserCase{"361_beams_180_deg", 361, 180.0, 0.0, false},
                      LaserCase{"laser_0_22_m_ahead", 271, 270.0, 0.22, false},
                      // Broke (rigidly aligned 4.04 m) while a closure between two recent nodes
                      // counted as evidence for a return; now 0.038 m, 0.176 m in the first
                      // scan's frame. See
                      // LoopCloser.AClosureBetweenTwoWaitingNodesIsNoEvidenceForAReturn.
                      LaserCase{"181_beams_180_deg", 181, 180.0, 0.0, false, 11, 0.25, 0.4},
                      // Broke (rigidly aligned 0.97 m) while a turned retry of the tracker could
                      // slide along a corridor; now 0.036 m, 0.30 m (max 0.57 m) in the first
                      // scan's frame, which a heading error early in the patrol turns. See
                      // Tracker.ATurnedRetryAlongACorridorKeepsOdometrysPosition.
                      LaserCase{"181_beams_180_deg_seed_9", 181, 180.0, 0.0, false, 9, 0.4, 0.8}),
    [](const ::testing::TestParamInfo<LaserCase>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace longterm_mapper2d
