#pragma once

#include <string>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/config/input_options.h"
#include "longterm_mapper2d/core/config/option_errors.h"

namespace longterm_mapper2d {

// Every option of the mapper, one section per module. The same YAML file (config/*.yaml)
// configures the offline tool and the ROS node.
struct MapperOptions {
  InputOptions input;

  template <class V>
  void Visit(V& v) {
    v.Section("input", input);
  }
  void Validate(OptionErrors& e) const { e.Section("input", input); }
};

// Loads a MapperOptions YAML file over the defaults; errors name every bad or unknown parameter.
Status LoadMapperOptions(const std::string& path, MapperOptions& options);

}  // namespace longterm_mapper2d
