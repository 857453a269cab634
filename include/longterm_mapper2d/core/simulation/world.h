#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/geometry/pose2.h"

namespace longterm_mapper2d {

struct Segment {
  Eigen::Vector2d a_m;
  Eigen::Vector2d b_m;
};

// A person walking a closed path of waypoints at a constant speed, seen by the laser as a circle.
struct SimulatedPerson {
  std::vector<Eigen::Vector2d> path_m;
  double speed_mps = 1.0;
  double radius_m = 0.25;
  double phase_s = 0.0;  // start offset along the path, in seconds of walking

  // Position at time t (seconds from the start of the session).
  Eigen::Vector2d PositionAt(double t_s) const;
};

// Objects that may differ between sessions (furniture, doors): present in the sessions listed
// (1-based), or in all sessions if the list is empty.
struct SemiStaticObject {
  std::string name;
  std::vector<Segment> segments;
  std::vector<int> sessions;
  bool PresentIn(int session) const;
};

// A 2D world: static walls, semi-static objects, people, and the robot's patrol route.
struct World {
  std::string name;
  std::vector<Segment> walls;
  std::vector<SemiStaticObject> objects;
  std::vector<SimulatedPerson> people;
  std::vector<Eigen::Vector2d> route_m;  // closed patrol route; the robot starts at route_m[0]
  double robot_speed_mps = 0.5;
  double robot_turn_rate_radps = 1.0;

  // Walls plus the semi-static objects of one session.
  std::vector<Segment> StaticSegments(int session) const;
};

// Loads a world from YAML. Keys: name, robot: {speed_mps, turn_rate_radps, route: [[x, y], ...]},
// walls: [[x1, y1, x2, y2], ...], boxes: [[xmin, ymin, xmax, ymax], ...] (static),
// objects: [{name, sessions: [1, 3], segments: [[...]], boxes: [[...]]}],
// people: [{speed_mps, radius_m, phase_s, path: [[x, y], ...]}]. Errors name the key.
StatusOr<World> LoadWorld(const std::string& path);
StatusOr<World> ParseWorld(const std::string& yaml_text);

// The four sides of an axis-aligned box.
std::vector<Segment> BoxSegments(double x_min, double y_min, double x_max, double y_max);

}  // namespace longterm_mapper2d
