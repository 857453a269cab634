#include "longterm_mapper2d/core/io/trajectory_io.h"

#include <gtest/gtest.h>

#include <fstream>

#include "testing/temp_dir.h"

namespace longterm_mapper2d {
namespace {

TEST(TrajectoryIo, RoundTripsAndNamesMalformedLines) {
  const test_support::ScopedTempDir dir("ltm_trajectory_io");
  ASSERT_FALSE(dir.path().empty());
  const std::string path = dir.path() + "/trajectory.txt";
  const std::vector<StampedPose2> trajectory = {{1.5, Pose2(1, 2, 0.3)}, {2.5, Pose2(-1, 0, -3.0)}};
  ASSERT_TRUE(WriteTrajectory(path, trajectory).ok());
  const auto read = ReadTrajectory(path);
  ASSERT_TRUE(read.ok());
  ASSERT_EQ(read->size(), 2u);
  EXPECT_NEAR((*read)[1].pose.theta(), -3.0, 1e-6);
  {
    std::ofstream out(path);
    out << "# header\n1 2 3 0.1\n\n2 3 x 0.2\n";
  }
  const auto bad = ReadTrajectory(path);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find(path + ":4:"), std::string::npos) << bad.status().message();
  {
    std::ofstream out(path);
    out << "1 2 3 0.1\n2 nan 3 0.2\n";
  }
  const auto not_finite = ReadTrajectory(path);
  ASSERT_FALSE(not_finite.ok());
  EXPECT_NE(not_finite.status().message().find(path + ":2:"), std::string::npos);
  EXPECT_FALSE(WriteTrajectory("/nonexistent/dir/t.txt", trajectory).ok());
}

}  // namespace
}  // namespace longterm_mapper2d
