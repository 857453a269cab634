#include "testing/simulated_mapping.h"

namespace longterm_mapper2d {
namespace test_support {

void AddSimulatedSteps(const std::vector<SimulatedStep>& steps, const Pose2& base_T_laser,
                       Mapper& mapper) {
  for (const SimulatedStep& step : steps) {
    ScanInput input;
    input.scan = step.scan;
    input.odom_T_base = step.odom_T_base;
    input.base_T_laser = base_T_laser;
    mapper.AddScan(input);
  }
}

void MapSimulatedSteps(const std::vector<SimulatedStep>& steps, const Pose2& base_T_laser,
                       Mapper& mapper) {
  AddSimulatedSteps(steps, base_T_laser, mapper);
  mapper.Finish();
}

std::vector<double> PositionErrors(const Mapper& mapper, const std::vector<SimulatedStep>& steps) {
  const auto trajectory = mapper.Trajectory();
  std::vector<double> errors;
  for (std::size_t i = 0; i < steps.size() && i < trajectory.size(); ++i) {
    errors.push_back((trajectory[i].pose.translation() - steps[i].map_T_base.translation()).norm());
  }
  return errors;
}

}  // namespace test_support
}  // namespace longterm_mapper2d
