#include "longterm_mapper2d/core/registration/nearest_neighbour_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace longterm_mapper2d {
namespace {

RichPoint MakePoint(double x, double y, double normal_angle) {
  RichPoint p;
  p.point_m = Eigen::Vector2d(x, y);
  p.normal = Eigen::Vector2d(std::cos(normal_angle), std::sin(normal_angle));
  return p;
}

// The definition: the nearest point with a normal, a compatible normal and d^2 < max_distance_sq.
int BruteForce(const Cloud& cloud, const Eigen::Vector2d& q, const Eigen::Vector2d& n,
               double cos_max_angle, double max_distance_sq) {
  int best = -1;
  double best_sq = max_distance_sq;
  for (int i = 0; i < static_cast<int>(cloud.size()); ++i) {
    const RichPoint& p = cloud[i];
    const double d2 = (q - p.point_m).squaredNorm();
    if (p.has_normal() && d2 < best_sq && n.dot(p.normal) > cos_max_angle) {
      best = i;
      best_sq = d2;
    }
  }
  return best;
}

// Walls of points (as local maps have) plus scattered points, some without a normal.
Cloud RandomCloud(std::mt19937& rng, double extent_m) {
  std::uniform_real_distribution<double> coordinate(-extent_m, extent_m), angle(-M_PI, M_PI);
  Cloud cloud;
  for (int wall = 0; wall < 12; ++wall) {
    const Eigen::Vector2d start(coordinate(rng), coordinate(rng));
    const double direction = angle(rng);
    for (int k = 0; k < 80; ++k) {
      const Eigen::Vector2d p =
          start + 0.03 * k * Eigen::Vector2d(std::cos(direction), std::sin(direction));
      cloud.push_back(MakePoint(p.x(), p.y(), direction + M_PI / 2));
    }
  }
  for (int k = 0; k < 300; ++k)
    cloud.push_back(MakePoint(coordinate(rng), coordinate(rng), angle(rng)));
  for (int k = 0; k < 50; ++k) {
    RichPoint p = MakePoint(coordinate(rng), coordinate(rng), 0.0);
    p.normal.setZero();  // no reliable normal: never a partner
    cloud.push_back(p);
  }
  return cloud;
}

TEST(NearestNeighbourGrid, FindsWhatABruteForceSearchFinds) {
  std::mt19937 rng(5);
  for (double radius : {0.25, 1.0, 3.0}) {
    for (double cell : {0.1, 0.5, 2.0}) {
      const Cloud cloud = RandomCloud(rng, 8.0);
      const NearestNeighbourGrid grid(cloud, radius, cell);
      std::uniform_real_distribution<double> coordinate(-11.0, 11.0), angle(-M_PI, M_PI);
      int found = 0;
      for (int k = 0; k < 3000; ++k) {
        const Eigen::Vector2d q(coordinate(rng), coordinate(rng));
        const double a = angle(rng);
        const Eigen::Vector2d n(std::cos(a), std::sin(a));
        // Also radii below the grid's own, as the fine stage of an alignment asks.
        const double r = k % 3 == 0 ? 0.5 * radius : radius;
        const double cos_max = k % 2 == 0 ? std::cos(0.8) : -2.0;
        const int expected = BruteForce(cloud, q, n, cos_max, r * r);
        const int got = grid.Nearest(q, n, cos_max, r * r);
        ASSERT_EQ(got, expected) << "radius " << radius << " cell " << cell << " query "
                                 << q.transpose();
        found += got >= 0;
      }
      EXPECT_GT(found, 100);  // the comparison covered hits, not only misses
    }
  }
}

TEST(NearestNeighbourGrid, QueriesOutsideTheCloudAndOnCellBorders) {
  Cloud cloud = {MakePoint(0.0, 0.0, 0.0), MakePoint(1.0, 0.0, 0.0), MakePoint(0.5, 0.5, 0.0)};
  const NearestNeighbourGrid grid(cloud, 1.0, 0.5);
  const Eigen::Vector2d n(1.0, 0.0);
  EXPECT_EQ(grid.Nearest({-0.9, 0.0}, n, 0.0, 1.0), 0);
  EXPECT_EQ(grid.Nearest({-1.0, 0.0}, n, 0.0, 1.0), -1);  // exactly at the radius: not within
  EXPECT_EQ(grid.Nearest({1.0, 0.9}, n, 0.0, 1.0), 2);
  EXPECT_EQ(grid.Nearest({1e9, -1e9}, n, 0.0, 1.0), -1);  // far away: no overflow
  EXPECT_EQ(grid.Nearest({0.0, 0.0}, -n, 0.0, 1.0), -1);  // normals disagree
  EXPECT_EQ(grid.Nearest({std::nan(""), 0.0}, n, 0.0, 1.0), -1);
}

TEST(NearestNeighbourGrid, EmptyAndHugeClouds) {
  const NearestNeighbourGrid empty(Cloud{}, 1.0);
  EXPECT_EQ(empty.Nearest({0.0, 0.0}, {1.0, 0.0}, 0.0, 1.0), -1);
  // Two points 200 km apart: the cells grow instead of allocating billions of them.
  const Cloud far = {MakePoint(0.0, 0.0, 0.0), MakePoint(2e5, 2e5, 0.0)};
  const NearestNeighbourGrid grid(far, 1.0);
  EXPECT_GT(grid.cell_m(), 50.0);
  EXPECT_EQ(grid.Nearest({2e5 - 0.3, 2e5}, {1.0, 0.0}, 0.0, 1.0), 1);
  EXPECT_EQ(grid.Nearest({0.2, 0.3}, {1.0, 0.0}, 0.0, 1.0), 0);
  EXPECT_EQ(grid.Nearest({1e5, 1e5}, {1.0, 0.0}, 0.0, 1.0), -1);
}

}  // namespace
}  // namespace longterm_mapper2d
