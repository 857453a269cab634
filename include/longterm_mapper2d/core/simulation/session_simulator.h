#pragma once

#include <cstdint>
#include <vector>

#include "longterm_mapper2d/core/config/option_errors.h"
#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/map/occupancy_grid.h"
#include "longterm_mapper2d/core/sensor/laser_scan.h"
#include "longterm_mapper2d/core/simulation/world.h"

namespace longterm_mapper2d {

// Distance from `origin` along `angle_rad` to the first segment or circle, or +inf if nothing is
// hit within max_range_m.
double CastRay(const std::vector<Segment>& segments, const std::vector<Eigen::Vector3d>& circles,
               const Eigen::Vector2d& origin, double angle_rad, double max_range_m);

struct SimulationOptions {
  double duration_s = 300.0;
  double rate_hz = 10.0;  // scans and odometry per second
  // Laser: beams over the field of view centred on the laser's x axis; no-return beams are +inf.
  int beams = 271;
  double fov_rad = 1.5 * M_PI;
  double max_range_m = 20.0;
  double range_noise_m = 0.01;
  double laser_x_m = 0.1;  // the laser sits this far ahead of the base
  // Every other scan starts half a beam later (a laser that interlaces two sweeps of its
  // resolution): consecutive scans have different angle_min.
  bool interlaced = false;
  // Odometry noise: per step, translation scaled by N(1, slip_per_m), rotation perturbed by
  // N(0, rotation_slip * |dtheta| + rotation_per_m * |d|), plus a heading drift per metre.
  double slip_per_m = 0.02;
  double rotation_slip = 0.03;
  double rotation_per_m = 0.005;
  double drift_rad_per_m = 0.002;

  template <class V>
  void Visit(V& v) {
    v("duration_s", duration_s);
    v("rate_hz", rate_hz);
    v("beams", beams);
    v("fov_rad", fov_rad);
    v("max_range_m", max_range_m);
    v("range_noise_m", range_noise_m);
    v("laser_x_m", laser_x_m);
    v("interlaced", interlaced);
    v("slip_per_m", slip_per_m);
    v("rotation_slip", rotation_slip);
    v("rotation_per_m", rotation_per_m);
    v("drift_rad_per_m", drift_rad_per_m);
  }
  void Validate(OptionErrors& e) const;
};

struct SimulatedStep {
  Pose2 map_T_base;   // truth
  Pose2 odom_T_base;  // what the wheels report
  LaserScan scan;     // in the laser frame, laser at base_T_laser
};

// Drives the robot around the world's patrol route (turn in place, then straight), with people
// walking and the semi-static objects of `session` (1-based). Deterministic for a seed.
class SessionSimulator {
 public:
  SessionSimulator(const World& world, int session, const SimulationOptions& options,
                   std::uint64_t seed);
  std::vector<SimulatedStep> Run();
  Pose2 base_T_laser() const { return Pose2(options_.laser_x_m, 0.0, 0.0); }

 private:
  const World& world_;
  int session_;
  SimulationOptions options_;
  std::uint64_t seed_;
};

// The static and semi-static world of a session as a grid: cells a segment touches are occupied
// (100; a segment on a grid line touches the cells on both sides), all others inside the world's
// bounds free (0).
OccupancyGrid RasterizeWorld(const World& world, int session, double resolution_m);

}  // namespace longterm_mapper2d
