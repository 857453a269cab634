#include "testing/synthetic_scans.h"

#include <cmath>
#include <random>

#include "longterm_mapper2d/core/cloud/scan_to_cloud.h"
#include "longterm_mapper2d/core/simulation/session_simulator.h"

namespace longterm_mapper2d {
namespace test_support {

LaserScan CastScan(const std::vector<Segment>& segments,
                   const std::vector<Eigen::Vector3d>& people, const Pose2& map_T_laser,
                   const SyntheticLaser& laser, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  LaserScan scan;
  scan.frame_id = "laser";
  const bool full = laser.fov_rad >= 2.0 * M_PI - 1e-9;
  scan.angle_increment_rad = full ? laser.fov_rad / laser.beams : laser.fov_rad / (laser.beams - 1);
  scan.angle_min_rad = full ? -M_PI : -laser.fov_rad / 2.0;
  scan.range_min_m = 0.05;
  scan.range_max_m = laser.max_range_m;
  scan.ranges.resize(laser.beams);
  for (int i = 0; i < laser.beams; ++i) {
    double r = CastRay(segments, people, map_T_laser.translation(),
                       map_T_laser.theta() + scan.BeamAngle(i), laser.max_range_m);
    if (std::isfinite(r) && laser.range_noise_m > 0.0) r += laser.range_noise_m * noise(rng);
    scan.ranges[i] = static_cast<float>(r);
  }
  return scan;
}

Cloud CloudSeenFrom(const std::vector<Segment>& segments, const Pose2& map_T_laser,
                    double max_range_m) {
  SyntheticLaser laser;
  laser.max_range_m = max_range_m;
  laser.range_noise_m = 0.005;
  return CloudFromScan(CastScan(segments, {}, map_T_laser, laser, 11), Pose2(), CloudOptions{});
}

std::vector<Segment> IrregularRoom() {
  auto seg = [](double x1, double y1, double x2, double y2) {
    return Segment{Eigen::Vector2d(x1, y1), Eigen::Vector2d(x2, y2)};
  };
  std::vector<Segment> s = {
      seg(-5, -3, 3, -3), seg(3, -3, 5, -1),   // slanted corner
      seg(5, -1, 5, 4),   seg(5, 4, 1, 4),     //
      seg(1, 4, 1, 5),    seg(1, 5, -2, 5),    // alcove
      seg(-2, 5, -2, 4),  seg(-2, 4, -5, 4),   //
      seg(-5, 4, -5, -3),
  };
  const auto pillar = BoxSegments(1.5, 0.5, 2.0, 1.2);
  s.insert(s.end(), pillar.begin(), pillar.end());
  const auto crate = BoxSegments(-3.5, -2.0, -2.7, -1.4);
  s.insert(s.end(), crate.begin(), crate.end());
  return s;
}

std::vector<Segment> Corridor() {
  return {Segment{Eigen::Vector2d(-20, -1), Eigen::Vector2d(20, -1)},
          Segment{Eigen::Vector2d(-20, 1), Eigen::Vector2d(20, 1)}};
}

}  // namespace test_support
}  // namespace longterm_mapper2d
