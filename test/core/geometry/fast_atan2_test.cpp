#include "longterm_mapper2d/core/geometry/fast_atan2.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace longterm_mapper2d {
namespace {

TEST(FastAtan2, AgreesWithTheLibraryAllAroundTheCircle) {
  double max_error = 0.0;
  // Directions all around, at ranges from millimetres to kilometres.
  for (int k = 0; k < 200000; ++k) {
    const double bearing = -M_PI + 2.0 * M_PI * (k + 0.37) / 200000.0;
    for (double range : {1e-3, 0.7, 25.0, 3e3}) {
      const double x = range * std::cos(bearing), y = range * std::sin(bearing);
      max_error = std::max(max_error, std::abs(FastAtan2(y, x) - std::atan2(y, x)));
    }
  }
  EXPECT_LT(max_error, 2e-8);
}

TEST(FastAtan2, AxesZerosAndNonFiniteValuesAreTheLibrarys) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [y, x] : {std::pair{0.0, 1.0}, {0.0, -1.0}, {-0.0, -1.0}, {1.0, 0.0},
                             {-1.0, 0.0}, {1.0, -0.0}, {0.0, 0.0}, {-0.0, -0.0}, {inf, 1.0},
                             {1.0, -inf}, {inf, inf}}) {
    EXPECT_NEAR(FastAtan2(y, x), std::atan2(y, x), 1e-15) << y << " " << x;
    EXPECT_EQ(std::signbit(FastAtan2(y, x)), std::signbit(std::atan2(y, x))) << y << " " << x;
  }
  // The diagonals are where the polynomial is farthest off.
  EXPECT_NEAR(FastAtan2(1.0, 1.0), M_PI / 4, 1e-8);
  EXPECT_NEAR(FastAtan2(-2.0, -2.0), -3 * M_PI / 4, 1e-8);
  EXPECT_TRUE(std::isnan(FastAtan2(nan, 1.0)));
  EXPECT_TRUE(std::isnan(FastAtan2(1.0, nan)));
}

}  // namespace
}  // namespace longterm_mapper2d
