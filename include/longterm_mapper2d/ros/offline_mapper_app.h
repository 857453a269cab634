#pragma once

namespace longterm_mapper2d_ros {

// The offline mapper: bags or a CARMEN log in, trajectory, map and statistics out. Runs the same
// conversions and the same core façade as mapper_node, with no roscore. Deterministic.
// Returns the process exit code (0 ok, 1 failure while mapping or writing, 2 bad arguments/input).
int RunOfflineMapper(int argc, char** argv);

}  // namespace longterm_mapper2d_ros
