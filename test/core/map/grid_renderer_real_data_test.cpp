// Rendering and map comparison on the GMapping-corrected Intel Research Lab log (910 keyframe
// scans with corrected poses; see ../shared/data/SOURCES.md §3). Quick: well under a second.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "longterm_mapper2d/core/evaluation/map_comparison.h"
#include "longterm_mapper2d/core/map/grid_renderer.h"

namespace longterm_mapper2d {
namespace {

// FLASER n r_1 .. r_n x y theta odom_x odom_y odom_theta ipc_stamp host logger_stamp; CARMEN
// beams start at -pi/2 with a step of pi/180 for 180 beams. Readings of 81.83 m are no-returns.
std::vector<PosedScan> ReadFlaserScans(const std::string& path) {
  std::vector<PosedScan> scans;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("FLASER ", 0) != 0) continue;
    std::istringstream fields(line.substr(7));
    int n = 0;
    fields >> n;
    PosedScan posed;
    posed.scan.angle_min_rad = -M_PI / 2;
    posed.scan.angle_increment_rad = M_PI / 180;
    posed.scan.range_min_m = 0.01;
    posed.scan.range_max_m = 81.0;
    posed.scan.ranges.resize(n);
    for (float& r : posed.scan.ranges) fields >> r;
    double x, y, theta;
    fields >> x >> y >> theta >> posed.scan.stamp_s >> posed.scan.stamp_s >> posed.scan.stamp_s;
    if (!fields) continue;
    posed.map_T_laser = Pose2(x, y, theta);
    scans.push_back(posed);
  }
  return scans;
}

TEST(RealData, IntelCorrectedLogRendersAndComparesWithItself) {
  const std::string path =
      std::string(LTM_SHARED_DATA_DIR) + "/radish-gfs-corrected/intel-corrected.log";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "skipped: no shared data at " << path;
  const std::vector<PosedScan> scans = ReadFlaserScans(path);
  ASSERT_EQ(scans.size(), 910u);

  GridOptions options;
  GridRenderStats stats;
  const auto truth = RenderOccupancyGrid(scans, options, &stats);
  ASSERT_TRUE(truth.ok()) << truth.status().message();
  EXPECT_EQ(stats.scans_used, 910);
  // The Intel lab is about 30 m x 30 m; no-return beams clear up to 10 m past the walls' gaps.
  EXPECT_GT(truth->width * truth->resolution_m, 30.0);
  EXPECT_LT(truth->width * truth->resolution_m, 70.0);
  int64_t occupied = 0, free = 0;
  for (const int8_t v : truth->cells) {
    occupied += v == 100;
    free += v == 0;
  }
  EXPECT_GT(occupied, 5000);
  EXPECT_LT(occupied, free / 5);

  // The same scans at a coarser resolution agree with the fine map almost everywhere.
  GridOptions coarse_options;
  coarse_options.resolution_m = 0.1;
  const auto coarse = RenderOccupancyGrid(scans, coarse_options);
  ASSERT_TRUE(coarse.ok());
  const auto same = CompareMaps(*coarse, *truth);
  ASSERT_TRUE(same.ok());
  EXPECT_GT(same->precision, 0.9);
  EXPECT_GT(same->recall, 0.9);
  EXPECT_LT(same->phantom_fraction, 0.05);

  // A heading drift of 2 degrees over the run bends the map: far lower precision, more phantoms.
  std::vector<PosedScan> drifted = scans;
  for (std::size_t k = 0; k < drifted.size(); ++k) {
    const Pose2 drift(0.0, 0.0, (2.0 * M_PI / 180.0) * k / drifted.size());
    drifted[k].map_T_laser = drift * drifted[k].map_T_laser;
  }
  const auto bent = RenderOccupancyGrid(drifted, options);
  ASSERT_TRUE(bent.ok());
  const auto worse = CompareMaps(*bent, *truth);
  ASSERT_TRUE(worse.ok());
  EXPECT_LT(worse->precision, same->precision - 0.1);
  EXPECT_GT(worse->phantom_fraction, same->phantom_fraction + 0.05);
  std::printf(
      "[ intel ] fine %dx%d cells, coarse vs fine P %.3f R %.3f phantom %.3f; drifted "
      "P %.3f R %.3f phantom %.3f\n",
      truth->width, truth->height, same->precision, same->recall, same->phantom_fraction,
      worse->precision, worse->recall, worse->phantom_fraction);
}

}  // namespace
}  // namespace longterm_mapper2d
