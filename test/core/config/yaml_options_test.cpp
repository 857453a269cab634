#include "longterm_mapper2d/core/config/yaml_options.h"

#include <gtest/gtest.h>

namespace longterm_mapper2d {
namespace {

struct InnerOptions {
  int iterations = 30;
  bool enabled = true;
  template <class V>
  void Visit(V& v) {
    v("iterations", iterations);
    v("enabled", enabled);
  }
  void Validate(OptionErrors& e) const {
    e.Require(iterations > 0, "iterations", "must be positive");
  }
};

struct OuterOptions {
  double range_m = 5.0;
  std::string mode = "mapping";
  InnerOptions inner;
  template <class V>
  void Visit(V& v) {
    v("range_m", range_m);
    v("mode", mode);
    v.Section("inner", inner);
  }
  void Validate(OptionErrors& e) const {
    e.Require(range_m > 0.0, "range_m", "must be positive");
    e.Section("inner", inner);
  }
};

TEST(YamlOptions, EmptyDocumentKeepsDefaults) {
  OuterOptions options;
  ASSERT_TRUE(LoadOptionsFromYamlString("", options).ok());
  EXPECT_EQ(options.inner.iterations, 30);
}

TEST(YamlOptions, ReadsNestedValues) {
  OuterOptions options;
  const Status s = LoadOptionsFromYamlString(
      "range_m: 2.5\nmode: localization\ninner: {iterations: 7, enabled: false}\n", options);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_DOUBLE_EQ(options.range_m, 2.5);
  EXPECT_EQ(options.mode, "localization");
  EXPECT_EQ(options.inner.iterations, 7);
  EXPECT_FALSE(options.inner.enabled);
}

TEST(YamlOptions, UnknownKeysAreReportedWithTheirPath) {
  OuterOptions options;
  const Status s = LoadOptionsFromYamlString("range_mm: 2\ninner: {iteration: 3}\n", options);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("range_mm: unknown parameter"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("inner/iteration: unknown parameter"), std::string::npos);
}

TEST(YamlOptions, WrongTypesAndInvalidValuesNameTheParameter) {
  OuterOptions options;
  Status s = LoadOptionsFromYamlString("inner: {iterations: 2.5}\n", options);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("inner/iterations"), std::string::npos) << s.message();

  options = OuterOptions();
  s = LoadOptionsFromYamlString("range_m: -1\ninner: {iterations: 0}\n", options);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("range_m: must be positive"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("inner/iterations: must be positive"), std::string::npos);

  s = LoadOptionsFromYamlString("inner: 3\n", options);
  EXPECT_FALSE(s.ok());
  s = LoadOptionsFromYamlString("[1, 2]", options);
  EXPECT_FALSE(s.ok());
  s = LoadOptionsFromYamlString("a: [", options);
  EXPECT_FALSE(s.ok());
}

TEST(YamlOptions, DumpRoundTrips) {
  OuterOptions options;
  options.range_m = 1.25;
  options.inner.iterations = 11;
  OuterOptions loaded;
  ASSERT_TRUE(LoadOptionsFromYamlString(OptionsToYaml(options), loaded).ok());
  EXPECT_DOUBLE_EQ(loaded.range_m, 1.25);
  EXPECT_EQ(loaded.inner.iterations, 11);
}

TEST(YamlOptions, MissingFileIsAnError) {
  OuterOptions options;
  const Status s = LoadOptionsFromYamlFile("/nonexistent/dir/options.yaml", options);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace longterm_mapper2d
