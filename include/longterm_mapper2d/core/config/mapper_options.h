#pragma once

#include <string>

#include "longterm_mapper2d/core/cloud/cloud_merger.h"
#include "longterm_mapper2d/core/cloud/scan_to_cloud.h"
#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/config/input_options.h"
#include "longterm_mapper2d/core/config/option_errors.h"
#include "longterm_mapper2d/core/graph/optimizer.h"
#include "longterm_mapper2d/core/loop_closing/loop_closing_options.h"
#include "longterm_mapper2d/core/map/grid_options.h"
#include "longterm_mapper2d/core/mapping/maintenance_options.h"
#include "longterm_mapper2d/core/mapping/motion_filter.h"
#include "longterm_mapper2d/core/mapping/tracker_options.h"
#include "longterm_mapper2d/core/mapping/trajectory_refiner.h"
#include "longterm_mapper2d/core/mapping/trajectory_smoothing.h"
#include "longterm_mapper2d/core/registration/registration_options.h"

namespace longterm_mapper2d {

// Every option of the mapper, one section per module. The same YAML file (config/*.yaml)
// configures the offline tool and the ROS node.
struct MapperOptions {
  InputOptions input;
  CloudOptions cloud;
  RegistrationOptions registration;
  MergerOptions merger;
  TrackerOptions tracker;
  MotionFilterOptions motion_filter;
  SessionOptions session;
  LocalizationOptions localization;
  LoopClosingOptions loop_closing;
  OptimizerOptions optimizer;
  MaintenanceOptions maintenance;
  GridOptions grid;
  TrajectorySmoothingOptions trajectory;
  TrajectoryRefinementOptions trajectory_refinement;

  template <class V>
  void Visit(V& v) {
    v.Section("input", input);
    v.Section("cloud", cloud);
    v.Section("registration", registration);
    v.Section("merger", merger);
    v.Section("tracker", tracker);
    v.Section("motion_filter", motion_filter);
    v.Section("session", session);
    v.Section("localization", localization);
    v.Section("loop_closing", loop_closing);
    v.Section("optimizer", optimizer);
    v.Section("maintenance", maintenance);
    v.Section("grid", grid);
    v.Section("trajectory", trajectory);
    v.Section("trajectory_refinement", trajectory_refinement);
  }
  void Validate(OptionErrors& e) const {
    e.Section("input", input);
    e.Section("cloud", cloud);
    e.Section("registration", registration);
    e.Section("merger", merger);
    e.Section("tracker", tracker);
    e.Section("motion_filter", motion_filter);
    e.Section("session", session);
    e.Section("localization", localization);
    e.Section("loop_closing", loop_closing);
    e.Section("optimizer", optimizer);
    e.Section("maintenance", maintenance);
    e.Section("grid", grid);
    e.Section("trajectory", trajectory);
    e.Section("trajectory_refinement", trajectory_refinement);
  }
};

// Loads a MapperOptions YAML file over the defaults; errors name every bad or unknown parameter.
Status LoadMapperOptions(const std::string& path, MapperOptions& options);

}  // namespace longterm_mapper2d
