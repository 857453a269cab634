#pragma once

#include <vector>

#include "longterm_mapper2d/core/geometry/pose2.h"
#include "longterm_mapper2d/core/mapping/mapper.h"
#include "longterm_mapper2d/core/simulation/session_simulator.h"

namespace longterm_mapper2d {
namespace test_support {

// Feeds simulated steps to the mapper as scans (the wheels' odometry, the laser at base_T_laser).
void AddSimulatedSteps(const std::vector<SimulatedStep>& steps, const Pose2& base_T_laser,
                       Mapper& mapper);

// The same, and finishes the session.
void MapSimulatedSteps(const std::vector<SimulatedStep>& steps, const Pose2& base_T_laser,
                       Mapper& mapper);

// Position error of the mapper's final trajectory at each step, against the simulated truth.
std::vector<double> PositionErrors(const Mapper& mapper, const std::vector<SimulatedStep>& steps);

}  // namespace test_support
}  // namespace longterm_mapper2d
