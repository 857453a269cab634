#pragma once

#include <string>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/mapping/mapper.h"

namespace longterm_mapper2d {

// Writes what a person looks at after mapping into `directory` (created if missing):
// map.pgm + map.yaml (map_server format), map.png (preview), trajectory.txt (stamp x y theta per
// input scan). The grid is rendered from the mapper's waypoint scans with its grid options.
Status WriteMapOutputs(const Mapper& mapper, const std::string& directory);

}  // namespace longterm_mapper2d
