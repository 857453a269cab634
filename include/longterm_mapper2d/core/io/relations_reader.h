#pragma once

#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/geometry/pose2.h"

namespace longterm_mapper2d {

// One ground-truth relation of the Kümmerle et al. (2009) benchmark: the base pose at stamp t2
// expressed in the base frame at stamp t1.
struct Relation {
  double t1_s = 0.0;
  double t2_s = 0.0;
  Pose2 t1_T_t2;
};

// Reads a `.relations` file: one relation per line, `t1 t2 x y z roll pitch yaw` (seconds, metres,
// radians); z, roll and pitch are ignored (they are 0 in the planar datasets). Blank lines and
// lines starting with '#' are skipped. A malformed line is an error "path:LINE: ...".
StatusOr<std::vector<Relation>> ReadRelations(const std::string& path);
// The same for the text of a file; errors name `source_name` instead of a path.
StatusOr<std::vector<Relation>> ParseRelations(const std::string& text,
                                               const std::string& source_name);

}  // namespace longterm_mapper2d
