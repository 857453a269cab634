#include "longterm_mapper2d/core/simulation/session_simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>

namespace longterm_mapper2d {
namespace {

// People keep at least this far from the robot's centre (plus their own radius).
constexpr double kRobotRadiusM = 0.45;

// The cells along one axis whose closed extent holds coordinate `v_m`: one cell, or the two
// either side when `v_m` lies on the line between them. A wall on a grid line (the worlds put
// walls at round coordinates) is the surface of both cells: a laser sees it from either side and
// its returns, with range noise, fall into both. Marking only the cell that floor() picks (which
// flips with the last bit of rounding) put half a cell of bias into the truth.
std::pair<int, int> CellsTouching(double v_m, double origin_m, double resolution_m) {
  const double f = (v_m - origin_m) / resolution_m;
  const double line = std::round(f);
  if (std::abs(f - line) < 1e-6) return {static_cast<int>(line) - 1, static_cast<int>(line)};
  const int cell = static_cast<int>(std::floor(f));
  return {cell, cell};
}

}  // namespace

void SimulationOptions::Validate(OptionErrors& e) const {
  e.Require(duration_s > 0.0, "duration_s", "must be positive");
  e.Require(rate_hz > 0.0 && rate_hz <= 100.0, "rate_hz", "must be in (0, 100]");
  e.Require(beams >= 2 && beams <= 10000, "beams", "must be in [2, 10000]");
  e.Require(fov_rad > 0.0 && fov_rad <= 2.0 * M_PI, "fov_rad", "must be in (0, 2*pi]");
  e.Require(max_range_m > 0.0, "max_range_m", "must be positive");
  e.Require(range_noise_m >= 0.0, "range_noise_m", "must be non-negative");
  e.Require(slip_per_m >= 0.0 && rotation_slip >= 0.0 && rotation_per_m >= 0.0, "slip_per_m",
            "noise parameters must be non-negative");
}

double CastRay(const std::vector<Segment>& segments, const std::vector<Eigen::Vector3d>& circles,
               const Eigen::Vector2d& origin, double angle_rad, double max_range_m) {
  const Eigen::Vector2d d(std::cos(angle_rad), std::sin(angle_rad));
  double best = max_range_m;
  bool hit = false;
  for (const Segment& s : segments) {
    // origin + t d = a + u (b - a): solve with 2D cross products.
    const Eigen::Vector2d e = s.b_m - s.a_m;
    const double denom = d.x() * e.y() - d.y() * e.x();
    if (std::abs(denom) < 1e-12) continue;
    const Eigen::Vector2d w = s.a_m - origin;
    const double t = (w.x() * e.y() - w.y() * e.x()) / denom;
    const double u = (w.x() * d.y() - w.y() * d.x()) / denom;
    if (t > 1e-9 && t < best && u >= 0.0 && u <= 1.0) {
      best = t;
      hit = true;
    }
  }
  for (const Eigen::Vector3d& c : circles) {
    // |origin + t d - c|^2 = r^2, nearest positive root.
    const Eigen::Vector2d w = origin - c.head<2>();
    const double b = w.dot(d);
    const double disc = b * b - (w.squaredNorm() - c.z() * c.z());
    if (disc < 0.0) continue;
    const double t = -b - std::sqrt(disc);
    if (t > 1e-9 && t < best) {
      best = t;
      hit = true;
    }
  }
  return hit ? best : std::numeric_limits<double>::infinity();
}

SessionSimulator::SessionSimulator(const World& world, int session,
                                   const SimulationOptions& options, std::uint64_t seed)
    : world_(world), session_(session), options_(options), seed_(seed) {}

std::vector<SimulatedStep> SessionSimulator::Run() {
  // One generator per noise source, so that changing one model does not reshuffle the others.
  std::mt19937_64 odometry_rng(seed_ * 7919 + 1), laser_rng(seed_ * 7919 + 2);
  std::normal_distribution<double> unit(0.0, 1.0);
  const std::vector<Segment> segments = world_.StaticSegments(session_);
  const double dt = 1.0 / options_.rate_hz;
  const Pose2 base_T_laser = this->base_T_laser();

  const auto& route = world_.route_m;
  const Eigen::Vector2d heading0 = route[1] - route[0];
  Pose2 truth(route[0], std::atan2(heading0.y(), heading0.x()));
  Pose2 odom = truth;
  std::size_t target = 1;
  std::vector<double> person_delay_s(world_.people.size(), 0.0);
  std::vector<SimulatedStep> steps;
  steps.reserve(static_cast<std::size_t>(options_.duration_s * options_.rate_hz) + 1);

  for (double t = 0.0; t < options_.duration_s; t += dt) {
    // Truth motion: turn towards the next waypoint, then drive to it.
    if ((route[target] - truth.translation()).norm() < 1e-3) target = (target + 1) % route.size();
    const Eigen::Vector2d to_target = route[target] - truth.translation();
    const double bearing = NormalizeAngle(std::atan2(to_target.y(), to_target.x()) - truth.theta());
    double forward = 0.0, turn = 0.0;
    const double max_turn = world_.robot_turn_rate_radps * dt;
    if (std::abs(bearing) > 0.02) {
      turn = std::clamp(bearing, -max_turn, max_turn);
    } else {
      turn = bearing;
      forward = std::min(world_.robot_speed_mps * dt, to_target.norm());
    }
    const Pose2 step(forward, 0.0, turn);
    truth = truth * step;

    // Odometry: the same step as the wheels measured it.
    const double d = std::abs(forward);
    const double noisy_forward = forward * (1.0 + options_.slip_per_m * unit(odometry_rng));
    const double rotation_sigma =
        options_.rotation_slip * std::abs(turn) + options_.rotation_per_m * d;
    const double noisy_turn =
        turn + rotation_sigma * unit(odometry_rng) + options_.drift_rad_per_m * d;
    odom = odom * Pose2(noisy_forward, 0.0, noisy_turn);

    // Laser at the true pose, people where they are now. A person about to walk into the robot
    // waits (people step aside for a robot; none walks through it).
    std::vector<Eigen::Vector3d> circles;
    for (std::size_t k = 0; k < world_.people.size(); ++k) {
      const auto& person = world_.people[k];
      Eigen::Vector2d p = person.PositionAt(t - person_delay_s[k]);
      if ((p - truth.translation()).norm() < person.radius_m + kRobotRadiusM) {
        person_delay_s[k] += dt;
        p = person.PositionAt(t - person_delay_s[k]);
      }
      circles.emplace_back(p.x(), p.y(), person.radius_m);
    }
    const Pose2 map_T_laser = truth * base_T_laser;
    LaserScan scan;
    scan.stamp_s = t;
    scan.frame_id = "laser";
    scan.angle_min_rad = -options_.fov_rad / 2.0;
    scan.angle_increment_rad = options_.fov_rad / (options_.beams - 1);
    if (options_.fov_rad >= 2.0 * M_PI - 1e-9)
      scan.angle_increment_rad = options_.fov_rad / options_.beams;
    if (options_.interlaced && steps.size() % 2 == 1) {
      scan.angle_min_rad += 0.5 * scan.angle_increment_rad;
    }
    scan.range_min_m = 0.05;
    scan.range_max_m = options_.max_range_m;
    scan.ranges.resize(options_.beams);
    for (int i = 0; i < options_.beams; ++i) {
      const double angle = map_T_laser.theta() + scan.BeamAngle(i);
      double range =
          CastRay(segments, circles, map_T_laser.translation(), angle, options_.max_range_m);
      if (std::isfinite(range)) {
        range += options_.range_noise_m * unit(laser_rng);
        if (range >= options_.max_range_m) range = std::numeric_limits<double>::infinity();
      }
      scan.ranges[i] = static_cast<float>(range);
    }
    steps.push_back({truth, odom, std::move(scan)});
  }
  return steps;
}

OccupancyGrid RasterizeWorld(const World& world, int session, double resolution_m) {
  const std::vector<Segment> segments = world.StaticSegments(session);
  Eigen::Vector2d lo(std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
  Eigen::Vector2d hi = -lo;
  for (const Segment& s : segments) {
    lo = lo.cwiseMin(s.a_m).cwiseMin(s.b_m);
    hi = hi.cwiseMax(s.a_m).cwiseMax(s.b_m);
  }
  if (segments.empty()) lo = hi = Eigen::Vector2d::Zero();
  lo -= Eigen::Vector2d::Constant(1.0);
  hi += Eigen::Vector2d::Constant(1.0);
  const int width = static_cast<int>(std::ceil((hi.x() - lo.x()) / resolution_m));
  const int height = static_cast<int>(std::ceil((hi.y() - lo.y()) / resolution_m));
  OccupancyGrid grid = OccupancyGrid::Filled(resolution_m, width, height, lo, 0);
  for (const Segment& s : segments) {
    const double length = (s.b_m - s.a_m).norm();
    const int samples = std::max(2, static_cast<int>(std::ceil(length / (0.25 * resolution_m))));
    for (int k = 0; k <= samples; ++k) {
      const Eigen::Vector2d p = s.a_m + (s.b_m - s.a_m) * (static_cast<double>(k) / samples);
      const auto [x_lo, x_hi] = CellsTouching(p.x(), lo.x(), resolution_m);
      const auto [y_lo, y_hi] = CellsTouching(p.y(), lo.y(), resolution_m);
      for (int iy = y_lo; iy <= y_hi; ++iy) {
        for (int ix = x_lo; ix <= x_hi; ++ix) {
          if (grid.InBounds(ix, iy)) grid.at(ix, iy) = 100;
        }
      }
    }
  }
  return grid;
}

}  // namespace longterm_mapper2d
