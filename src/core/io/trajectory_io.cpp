#include "longterm_mapper2d/core/io/trajectory_io.h"

#include <cstdio>
#include <fstream>

#include "longterm_mapper2d/core/io/number_table.h"

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
  const auto rows = ReadNumberTable(path, 4, "'stamp x y theta'");
  if (!rows.ok()) return rows.status();
  std::vector<StampedPose2> trajectory;
  trajectory.reserve(rows->size());
  for (const NumberRow& row : *rows) {
    const std::vector<double>& v = row.values;
    trajectory.push_back({v[0], Pose2(v[1], v[2], v[3])});
  }
  return trajectory;
}

}  // namespace longterm_mapper2d
