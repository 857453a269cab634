#include "longterm_mapper2d/core/config/mapper_options.h"

#include "longterm_mapper2d/core/config/yaml_options.h"

namespace longterm_mapper2d {

Status LoadMapperOptions(const std::string& path, MapperOptions& options) {
  return LoadOptionsFromYamlFile(path, options);
}

}  // namespace longterm_mapper2d
