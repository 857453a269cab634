#include "longterm_mapper2d/core/simulation/world.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>

#include "longterm_mapper2d/core/config/yaml_options.h"

namespace longterm_mapper2d {

Eigen::Vector2d SimulatedPerson::PositionAt(double t_s) const {
  if (path_m.empty()) return Eigen::Vector2d::Zero();
  if (path_m.size() == 1 || speed_mps <= 0.0) return path_m.front();
  double length = 0.0;
  for (std::size_t i = 0; i < path_m.size(); ++i) {
    length += (path_m[(i + 1) % path_m.size()] - path_m[i]).norm();
  }
  if (length <= 0.0) return path_m.front();
  double s = std::fmod((t_s + phase_s) * speed_mps, length);
  if (s < 0.0) s += length;
  for (std::size_t i = 0; i < path_m.size(); ++i) {
    const Eigen::Vector2d& a = path_m[i];
    const Eigen::Vector2d& b = path_m[(i + 1) % path_m.size()];
    const double leg = (b - a).norm();
    if (s <= leg && leg > 0.0) return a + (b - a) * (s / leg);
    s -= leg;
  }
  return path_m.front();
}

bool SemiStaticObject::PresentIn(int session) const {
  return sessions.empty() || std::find(sessions.begin(), sessions.end(), session) != sessions.end();
}

std::vector<Segment> World::StaticSegments(int session) const {
  std::vector<Segment> segments = walls;
  for (const auto& object : objects) {
    if (object.PresentIn(session)) {
      segments.insert(segments.end(), object.segments.begin(), object.segments.end());
    }
  }
  return segments;
}

std::vector<Segment> BoxSegments(double x_min, double y_min, double x_max, double y_max) {
  const Eigen::Vector2d a(x_min, y_min), b(x_max, y_min), c(x_max, y_max), d(x_min, y_max);
  return {{a, b}, {b, c}, {c, d}, {d, a}};
}

namespace {

// Reads a list of fixed-size number tuples, e.g. [[x1, y1, x2, y2], ...].
Status ReadTuples(const YAML::Node& node, std::size_t size, const std::string& key,
                  std::vector<std::vector<double>>& out) {
  if (!node.IsDefined() || node.IsNull()) return Status::Ok();
  if (!node.IsSequence()) return Status::Error(key + ": expected a list");
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    if (!item.IsSequence() || item.size() != size) {
      return Status::Error(key + "[" + std::to_string(i) + "]: expected " + std::to_string(size) +
                           " numbers");
    }
    std::vector<double> values;
    for (std::size_t k = 0; k < size; ++k) {
      try {
        values.push_back(item[k].as<double>());
      } catch (const std::exception&) {
        return Status::Error(key + "[" + std::to_string(i) + "]: not a number");
      }
      if (!std::isfinite(values.back())) {
        return Status::Error(key + "[" + std::to_string(i) + "]: not finite");
      }
    }
    out.push_back(values);
  }
  return Status::Ok();
}

Status ReadSegmentsAndBoxes(const YAML::Node& node, const std::string& prefix,
                            std::vector<Segment>& out) {
  std::vector<std::vector<double>> tuples;
  if (Status s = ReadTuples(node["segments"], 4, prefix + "segments", tuples); !s.ok()) return s;
  if (Status s = ReadTuples(node["walls"], 4, prefix + "walls", tuples); !s.ok()) return s;
  for (const auto& t : tuples) out.push_back({{t[0], t[1]}, {t[2], t[3]}});
  tuples.clear();
  if (Status s = ReadTuples(node["boxes"], 4, prefix + "boxes", tuples); !s.ok()) return s;
  for (const auto& t : tuples) {
    if (!(t[2] > t[0] && t[3] > t[1])) return Status::Error(prefix + "boxes: need min < max");
    const auto box = BoxSegments(t[0], t[1], t[2], t[3]);
    out.insert(out.end(), box.begin(), box.end());
  }
  return Status::Ok();
}

Status ReadPoints(const YAML::Node& node, const std::string& key,
                  std::vector<Eigen::Vector2d>& out) {
  std::vector<std::vector<double>> tuples;
  if (Status s = ReadTuples(node, 2, key, tuples); !s.ok()) return s;
  for (const auto& t : tuples) out.emplace_back(t[0], t[1]);
  return Status::Ok();
}

Status CheckKeys(const YAML::Node& node, const std::vector<std::string>& allowed,
                 const std::string& prefix) {
  if (!node.IsMap()) return Status::Error(prefix + ": expected a map");
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      return Status::Error(prefix + key + ": unknown key");
    }
  }
  return Status::Ok();
}

}  // namespace

StatusOr<World> ParseWorld(const std::string& yaml_text) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const std::exception& e) {
    return Status::Error(std::string("invalid YAML: ") + e.what());
  }
  if (Status s = CheckKeys(root, {"name", "robot", "walls", "boxes", "objects", "people"}, "");
      !s.ok()) {
    return s;
  }
  World world;
  try {
    world.name = root["name"] ? root["name"].as<std::string>() : "world";
    if (Status s = ReadSegmentsAndBoxes(root, "", world.walls); !s.ok()) return s;
    const YAML::Node robot = root["robot"];
    if (!robot) return Status::Error("robot: missing (it holds the patrol route)");
    if (Status s = CheckKeys(robot, {"speed_mps", "turn_rate_radps", "route"}, "robot/"); !s.ok()) {
      return s;
    }
    if (robot["speed_mps"]) world.robot_speed_mps = robot["speed_mps"].as<double>();
    if (robot["turn_rate_radps"]) world.robot_turn_rate_radps = robot["turn_rate_radps"].as<double>();
    if (Status s = ReadPoints(robot["route"], "robot/route", world.route_m); !s.ok()) return s;
    if (world.route_m.size() < 2) return Status::Error("robot/route: needs at least 2 points");
    if (!(world.robot_speed_mps > 0.0 && world.robot_speed_mps < 5.0)) {
      return Status::Error("robot/speed_mps: must be in (0, 5)");
    }
    if (!(world.robot_turn_rate_radps > 0.0)) {
      return Status::Error("robot/turn_rate_radps: must be positive");
    }
    const YAML::Node objects = root["objects"];
    for (std::size_t i = 0; objects && i < objects.size(); ++i) {
      const std::string prefix = "objects[" + std::to_string(i) + "]/";
      if (Status s = CheckKeys(objects[i], {"name", "sessions", "segments", "boxes"}, prefix);
          !s.ok()) {
        return s;
      }
      SemiStaticObject object;
      object.name = objects[i]["name"] ? objects[i]["name"].as<std::string>() : "object";
      if (objects[i]["sessions"]) object.sessions = objects[i]["sessions"].as<std::vector<int>>();
      if (Status s = ReadSegmentsAndBoxes(objects[i], prefix, object.segments); !s.ok()) return s;
      world.objects.push_back(object);
    }
    const YAML::Node people = root["people"];
    for (std::size_t i = 0; people && i < people.size(); ++i) {
      const std::string prefix = "people[" + std::to_string(i) + "]/";
      if (Status s = CheckKeys(people[i], {"speed_mps", "radius_m", "phase_s", "path"}, prefix);
          !s.ok()) {
        return s;
      }
      SimulatedPerson person;
      if (people[i]["speed_mps"]) person.speed_mps = people[i]["speed_mps"].as<double>();
      if (people[i]["radius_m"]) person.radius_m = people[i]["radius_m"].as<double>();
      if (people[i]["phase_s"]) person.phase_s = people[i]["phase_s"].as<double>();
      if (Status s = ReadPoints(people[i]["path"], prefix + "path", person.path_m); !s.ok()) {
        return s;
      }
      if (person.path_m.empty()) return Status::Error(prefix + "path: needs at least 1 point");
      if (!(person.speed_mps >= 0.0 && person.speed_mps <= 3.0)) {
        return Status::Error(prefix + "speed_mps: must be in [0, 3]");
      }
      if (!(person.radius_m > 0.0 && person.radius_m < 1.0)) {
        return Status::Error(prefix + "radius_m: must be in (0, 1)");
      }
      world.people.push_back(person);
    }
  } catch (const std::exception& e) {
    return Status::Error(std::string("invalid world: ") + e.what());
  }
  return world;
}

StatusOr<World> LoadWorld(const std::string& path) {
  std::string text;
  if (Status s = ReadTextFile(path, text); !s.ok()) return s;
  auto world = ParseWorld(text);
  if (!world.ok()) return Status::Error(path + ": " + world.status().message());
  return world;
}

}  // namespace longterm_mapper2d
