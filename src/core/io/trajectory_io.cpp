#include "longterm_mapper2d/core/io/trajectory_io.h"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace longterm_mapper2d {

Status WriteTrajectory(const std::string& path, const std::vector<StampedPose2>& trajectory) {
  std::ofstream out(path);
  if (!out) return Status::Error("cannot open '" + path + "' for writing");
  char line[160];
  for (const auto& entry : trajectory) {
    std::snprintf(line, sizeof(line), "%.6f %.6f %.6f %.6f\n", entry.stamp_s, entry.pose.x(),
                  entry.pose.y(), entry.pose.theta());
    out << line;
  }
  out.flush();
  if (!out) return Status::Error("error while writing '" + path + "'");
  return Status::Ok();
}

StatusOr<std::vector<StampedPose2>> ReadTrajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Status::Error("cannot open '" + path + "'");
  std::vector<StampedPose2> trajectory;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    double stamp, x, y, theta;
    std::string extra;
    if (!(fields >> stamp >> x >> y >> theta) || (fields >> extra)) {
      return Status::Error(path + ":" + std::to_string(line_number) +
                           ": expected 'stamp x y theta', got '" + line + "'");
    }
    trajectory.push_back({stamp, Pose2(x, y, theta)});
  }
  return trajectory;
}

}  // namespace longterm_mapper2d
