#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "longterm_mapper2d/core/cloud/rich_point.h"
#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"
#include "longterm_mapper2d/core/simulation/world.h"

namespace longterm_mapper2d {
namespace test_support {

// A laser for synthetic scans: `beams` over `fov_rad` centred on the laser x axis.
struct SyntheticLaser {
  int beams = 360;
  double fov_rad = 2.0 * M_PI;
  double max_range_m = 20.0;
  double range_noise_m = 0.0;
};

// Ray-casts segments and round people (x, y, radius) from map_T_laser into a scan; beams that hit
// nothing are +inf (no return).
LaserScan CastScan(const std::vector<Segment>& segments,
                   const std::vector<Eigen::Vector3d>& people, const Pose2& map_T_laser,
                   const SyntheticLaser& laser, std::uint64_t seed = 0);

// The cloud (default CloudOptions, laser at the base) of a scan of `segments` from `map_T_laser`
// with a full-circle laser of `max_range_m` and 5 mm range noise (seed 11): a local map's worth.
Cloud CloudSeenFrom(const std::vector<Segment>& segments, const Pose2& map_T_laser,
                    double max_range_m);

// An irregular room (not symmetric, so that registration has a unique answer): 10 m x 7 m with an
// alcove, a pillar and a slanted wall.
std::vector<Segment> IrregularRoom();

// A long straight corridor along x, 2 m wide, from x = -20 to 20: ambiguous along x.
std::vector<Segment> Corridor();

}  // namespace test_support
}  // namespace longterm_mapper2d
