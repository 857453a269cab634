#include "longterm_mapper2d/core/sensor/odometry_buffer.h"

#include <gtest/gtest.h>

namespace longterm_mapper2d {
namespace {

TEST(OdometryBuffer, InterpolatesInsideAndRefusesOutside) {
  OdometryBuffer buffer;
  ASSERT_TRUE(buffer.Add(1.0, Pose2(0, 0, M_PI - 0.1)).ok());
  ASSERT_TRUE(buffer.Add(2.0, Pose2(2, 0, -M_PI + 0.1)).ok());
  const auto mid = buffer.Interpolate(1.5);
  ASSERT_TRUE(mid.has_value());
  EXPECT_NEAR(mid->x(), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(mid->theta()), M_PI, 1e-12);
  EXPECT_FALSE(buffer.Interpolate(0.5).has_value());
  EXPECT_FALSE(buffer.Interpolate(2.5).has_value());
  EXPECT_TRUE(buffer.Interpolate(2.05, 0.1).has_value());
  EXPECT_NEAR(buffer.Interpolate(2.0)->x(), 2.0, 1e-12);
}

TEST(OdometryBuffer, RefusesTimeGoingBackwardsAndNonFiniteSamples) {
  OdometryBuffer buffer;
  ASSERT_TRUE(buffer.Add(5.0, Pose2()).ok());
  EXPECT_FALSE(buffer.Add(4.0, Pose2()).ok());
  EXPECT_FALSE(buffer.Add(6.0, Pose2(NAN, 0, 0)).ok());
  EXPECT_TRUE(buffer.Add(5.0, Pose2(1, 0, 0)).ok());  // same stamp replaces
  EXPECT_EQ(buffer.size(), 1u);
  EXPECT_NEAR(buffer.Interpolate(5.0)->x(), 1.0, 1e-12);
}

TEST(OdometryBuffer, TrimKeepsTheSampleBeforeTheCut) {
  OdometryBuffer buffer;
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(buffer.Add(i, Pose2(i, 0, 0)).ok());
  buffer.TrimBefore(5.5);
  EXPECT_EQ(buffer.front_stamp_s(), 5.0);
  EXPECT_NEAR(buffer.Interpolate(5.5)->x(), 5.5, 1e-12);
}

}  // namespace
}  // namespace longterm_mapper2d
