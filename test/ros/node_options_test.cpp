#include "longterm_mapper2d/ros/node_options.h"

#include <gtest/gtest.h>

#include "longterm_mapper2d/core/config/yaml_options.h"

namespace longterm_mapper2d_ros {
namespace {

TEST(NodeOptions, EveryShippedPresetLoads) {
  for (const char* preset : {"freiburg", "stata_pr2", "strands"}) {
    NodeOptions options;
    const auto s = longterm_mapper2d::LoadOptionsFromYamlFile(
        std::string(LTM_CONFIG_DIR) + "/presets/" + preset + ".yaml", options);
    EXPECT_TRUE(s.ok()) << preset << ": " << s.message();
  }
  NodeOptions stata;
  ASSERT_TRUE(longterm_mapper2d::LoadOptionsFromYamlFile(
                  std::string(LTM_CONFIG_DIR) + "/presets/stata_pr2.yaml", stata)
                  .ok());
  EXPECT_EQ(stata.scan_topic, "/base_scan");
  EXPECT_EQ(stata.odom_frame, "odom_combined");
  EXPECT_EQ(stata.base_frame, "base_footprint");
}

TEST(NodeOptions, InvalidValuesNameTheParameter) {
  NodeOptions options;
  const auto s = longterm_mapper2d::LoadOptionsFromYamlString(
      "odom_frame: map\ntf_publish_rate_hz: 0\nscan_topik: /scan\n", options);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("scan_topik: unknown parameter"), std::string::npos);
  EXPECT_NE(s.message().find("tf_publish_rate_hz"), std::string::npos);
  EXPECT_NE(s.message().find("map_frame: must differ from odom_frame"), std::string::npos);
}

TEST(NodeOptions, TheTfHistoryMustOutlastTheOdometryWait) {
  NodeOptions options;
  EXPECT_TRUE(longterm_mapper2d::LoadOptionsFromYamlString("tf_cache_s: 30\n", options).ok());
  EXPECT_DOUBLE_EQ(options.tf_cache_s, 30.0);
  const auto s =
      longterm_mapper2d::LoadOptionsFromYamlString("odometry_wait_s: 10\ntf_cache_s: 8\n", options);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("tf_cache_s: must exceed odometry_wait_s"), std::string::npos);
}

}  // namespace
}  // namespace longterm_mapper2d_ros
