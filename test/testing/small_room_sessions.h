#pragma once

#include <cstdint>
#include <vector>

#include "longterm_mapper2d/core/map/session_map_file.h"
#include "longterm_mapper2d/core/map/trajectory_anchors.h"
#include "longterm_mapper2d/core/mapping/mapper.h"
#include "longterm_mapper2d/core/simulation/session_simulator.h"

namespace longterm_mapper2d {
namespace test_support {

// What mapping one simulated session of the small room leaves.
struct SessionResult {
  SessionMap map;
  std::vector<AnchoredPose> anchors;
  std::vector<StampedPose2> trajectory;
  std::vector<SimulatedStep> steps;
  double max_error_m = 0.0;
  int session_id = -1;
  std::uint64_t merges = 0;
};

// Default mapper options with maintenance on or off.
MapperOptions WithMaintenance(bool enabled);

// The simulator of one 60 s session of the small room.
SessionSimulator SmallRoomSession(const World& world, int session, std::uint64_t seed);

// Maps one simulated session of the small room (seed 40 + session), optionally on top of a saved
// map.
SessionResult MapSession(const World& world, int session, const SessionMap* previous,
                         const MapperOptions& options = MapperOptions{});

}  // namespace test_support
}  // namespace longterm_mapper2d
