#include "longterm_mapper2d/ros/conversions.h"

#include <gtest/gtest.h>
#include <sensor_msgs/point_cloud2_iterator.h>

namespace longterm_mapper2d_ros {
namespace {

TEST(Conversions, CloudsBecomePointCloud2EvenWhenEmpty) {
  // The node publishes the tracker's local map before the first scan: an empty cloud.
  const sensor_msgs::PointCloud2 empty = ToRosCloud({}, "map", ros::Time(1.0));
  EXPECT_EQ(empty.width * empty.height, 0u);
  EXPECT_TRUE(empty.data.empty());
  EXPECT_EQ(empty.header.frame_id, "map");

  longterm_mapper2d::Cloud cloud(3);
  for (int i = 0; i < 3; ++i) cloud[i].point_m = Eigen::Vector2d(i, -i);
  sensor_msgs::PointCloud2 msg = ToRosCloud(cloud, "map", ros::Time(1.0));
  ASSERT_EQ(msg.width * msg.height, 3u);
  sensor_msgs::PointCloud2ConstIterator<float> x(msg, "x"), y(msg, "y");
  for (int i = 0; i < 3; ++i, ++x, ++y) {
    EXPECT_FLOAT_EQ(*x, static_cast<float>(i));
    EXPECT_FLOAT_EQ(*y, static_cast<float>(-i));
  }
}

}  // namespace
}  // namespace longterm_mapper2d_ros
