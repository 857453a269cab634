#include "testing/small_room_sessions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>

#include "testing/simulated_mapping.h"

namespace longterm_mapper2d {
namespace test_support {

MapperOptions WithMaintenance(bool enabled) {
  MapperOptions options;
  options.maintenance.enabled = enabled;
  return options;
}

SessionSimulator SmallRoomSession(const World& world, int session, std::uint64_t seed) {
  SimulationOptions simulation;
  simulation.duration_s = 60.0;
  return SessionSimulator(world, session, simulation, seed);
}

SessionResult MapSession(const World& world, int session, const SessionMap* previous,
                         const MapperOptions& options) {
  SessionSimulator simulator = SmallRoomSession(world, session, 40 + session);
  const auto steps = simulator.Run();
  Mapper mapper(options);
  if (previous) {
    EXPECT_TRUE(mapper.LoadSession(*previous, std::nullopt).ok());
  }
  MapSimulatedSteps(steps, simulator.base_T_laser(), mapper);
  SessionResult result;
  for (const double error_m : PositionErrors(mapper, steps)) {
    result.max_error_m = std::max(result.max_error_m, error_m);
  }
  result.session_id = mapper.session_id();
  result.map = mapper.ExportSession();
  result.anchors = mapper.TrajectoryAnchors();
  result.trajectory = mapper.Trajectory();
  result.steps = steps;
  const auto merges = mapper.stats().counters.find("merges");
  result.merges = merges == mapper.stats().counters.end() ? 0 : merges->second;
  return result;
}

}  // namespace test_support
}  // namespace longterm_mapper2d
