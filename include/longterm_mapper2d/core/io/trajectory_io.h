#pragma once

#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/geometry/pose2.h"

namespace longterm_mapper2d {

// Trajectory text files: one pose per line, `stamp x y theta` (seconds, metres, radians); blank
// lines and lines starting with '#' are ignored.
Status WriteTrajectory(const std::string& path, const std::vector<StampedPose2>& trajectory);
StatusOr<std::vector<StampedPose2>> ReadTrajectory(const std::string& path);

}  // namespace longterm_mapper2d
