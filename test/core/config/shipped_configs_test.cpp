// Every YAML shipped in config/ (except the world files, tested with the simulator) loads through
// the real loader, and mapping.yaml states exactly the defaults.
#include <dirent.h>
#include <gtest/gtest.h>

#include "longterm_mapper2d/core/config/mapper_options.h"
#include "longterm_mapper2d/core/config/yaml_options.h"

namespace longterm_mapper2d {
namespace {

std::vector<std::string> YamlFiles(const std::string& dir) {
  std::vector<std::string> files;
  if (DIR* d = ::opendir(dir.c_str())) {
    while (dirent* entry = ::readdir(d)) {
      const std::string name = entry->d_name;
      if (name.size() > 5 && name.substr(name.size() - 5) == ".yaml") files.push_back(dir + "/" + name);
    }
    ::closedir(d);
  }
  return files;
}

TEST(ShippedConfigs, EveryMapperConfigLoads) {
  const auto files = YamlFiles(LTM_CONFIG_DIR);
  ASSERT_GE(files.size(), 2u);
  for (const std::string& file : files) {
    MapperOptions options;
    const Status s = LoadMapperOptions(file, options);
    EXPECT_TRUE(s.ok()) << file << ": " << s.message();
  }
}

TEST(ShippedConfigs, MappingYamlStatesTheDefaults) {
  MapperOptions loaded;
  ASSERT_TRUE(LoadMapperOptions(std::string(LTM_CONFIG_DIR) + "/mapping.yaml", loaded).ok());
  EXPECT_EQ(OptionsToYaml(loaded), OptionsToYaml(MapperOptions{}));
}

TEST(ShippedConfigs, OdometryOnlyTurnsScanMatchingOff) {
  MapperOptions loaded;
  ASSERT_TRUE(LoadMapperOptions(std::string(LTM_CONFIG_DIR) + "/odometry_only.yaml", loaded).ok());
  EXPECT_FALSE(loaded.tracker.scan_matching);
}

}  // namespace
}  // namespace longterm_mapper2d
