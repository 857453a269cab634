#include "longterm_mapper2d/core/map/grid_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace longterm_mapper2d {
namespace {

// What one beam contributes: a free ray from the sensor to `length_m`, with an occupied endpoint
// when `hit`.
struct Beam {
  bool used = false;
  bool hit = false;
  double length_m = 0.0;
};

Beam ClassifyBeam(const LaserScan& scan, float range_m, const GridOptions& options) {
  Beam beam;
  if (std::isnan(range_m) || range_m < scan.range_min_m) return beam;
  if (std::isfinite(range_m) && range_m < scan.range_max_m && range_m <= options.max_range_m) {
    beam.used = true;
    beam.hit = true;
    beam.length_m = range_m;
    return beam;
  }
  // No return, or a return too far to trust: the beam crossed at least the capped free range.
  if (options.free_space_max_range_m <= 0.0) return beam;
  beam.used = true;
  beam.length_m = std::isfinite(range_m) ? std::min<double>(range_m, options.free_space_max_range_m)
                                         : options.free_space_max_range_m;
  return beam;
}

bool ScanUsable(const PosedScan& posed) {
  return posed.map_T_laser.IsFinite() && posed.scan.ValidateGeometry().ok();
}

double Logit(double p) { return std::log(p / (1.0 - p)); }

// Per-cell state of the renderer.
class LogOddsGrid {
 public:
  LogOddsGrid(const OccupancyGrid& frame, const GridOptions& options)
      : width_(frame.width),
        height_(frame.height),
        options_(options),
        log_odds_(frame.cells.size(), 0.0f),
        last_scan_(frame.cells.size(), 0) {}

  // Applies `delta` to a cell unless scan `scan_id` (>= 1) already updated it.
  void Update(int ix, int iy, int32_t scan_id, double delta) {
    if (ix < 0 || iy < 0 || ix >= width_ || iy >= height_) return;
    const std::size_t i = static_cast<std::size_t>(iy) * width_ + ix;
    if (last_scan_[i] == scan_id) return;
    last_scan_[i] = scan_id;
    const double updated =
        std::clamp(log_odds_[i] + delta, options_.log_odds_min, options_.log_odds_max);
    log_odds_[i] = static_cast<float>(updated);
  }

  // Integer Bresenham from (x0, y0) to (x1, y1), excluding the last cell.
  void TraceFree(int x0, int y0, int x1, int y1, int32_t scan_id) {
    const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
    const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    int error = dx + dy;
    while (x0 != x1 || y0 != y1) {
      Update(x0, y0, scan_id, options_.log_odds_miss);
      const int e2 = 2 * error;
      if (e2 >= dy) {
        error += dy;
        x0 += sx;
      }
      if (e2 <= dx) {
        error += dx;
        y0 += sy;
      }
    }
  }

  void WriteInto(OccupancyGrid& grid) const {
    const double occupied_logit = Logit(options_.occupied_threshold);
    const double free_logit = Logit(options_.free_threshold);
    for (std::size_t i = 0; i < grid.cells.size(); ++i) {
      if (last_scan_[i] == 0) {
        grid.cells[i] = OccupancyGrid::kUnknown;
      } else if (log_odds_[i] >= occupied_logit) {
        grid.cells[i] = OccupancyGrid::kOccupied;
      } else if (log_odds_[i] <= free_logit) {
        grid.cells[i] = OccupancyGrid::kFree;
      } else {
        const double p = 1.0 - 1.0 / (1.0 + std::exp(static_cast<double>(log_odds_[i])));
        grid.cells[i] = static_cast<int8_t>(std::clamp<long>(std::lround(100.0 * p), 1, 99));
      }
    }
  }

 private:
  int width_;
  int height_;
  GridOptions options_;
  std::vector<float> log_odds_;
  std::vector<int32_t> last_scan_;  // id of the last scan that updated the cell; 0 = never
};

}  // namespace

StatusOr<OccupancyGrid> RenderOccupancyGrid(const std::vector<PosedScan>& scans,
                                            const GridOptions& options, GridRenderStats* stats) {
  OptionErrors option_errors;
  options.Validate(option_errors);
  if (!option_errors.empty()) return Status::Error("grid options: " + option_errors.ToString());
  GridRenderStats local_stats;
  GridRenderStats& s = stats != nullptr ? *stats : local_stats;
  s = GridRenderStats();

  // Pass 1: bounds of everything the beams reach.
  Eigen::Vector2d min_m = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d max_m = -min_m;
  std::vector<char> usable(scans.size(), 0);
  for (std::size_t k = 0; k < scans.size(); ++k) {
    const PosedScan& posed = scans[k];
    if (!ScanUsable(posed)) {
      ++s.scans_skipped;
      continue;
    }
    usable[k] = 1;
    ++s.scans_used;
    const Eigen::Vector2d sensor = posed.map_T_laser.translation();
    min_m = min_m.cwiseMin(sensor);
    max_m = max_m.cwiseMax(sensor);
    for (std::size_t i = 0; i < posed.scan.ranges.size(); ++i) {
      const Beam beam = ClassifyBeam(posed.scan, posed.scan.ranges[i], options);
      if (!beam.used) continue;
      const double angle = posed.map_T_laser.theta() + posed.scan.BeamAngle(i);
      const Eigen::Vector2d end =
          sensor + beam.length_m * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      min_m = min_m.cwiseMin(end);
      max_m = max_m.cwiseMax(end);
    }
  }
  if (s.scans_used == 0) return Status::Error("no usable scan to render");

  const double res = options.resolution_m;
  const Eigen::Vector2d origin = ((min_m.array() - options.margin_m) / res).floor().matrix() * res;
  const Eigen::Vector2d cells_needed = ((max_m - origin).array() + options.margin_m) / res;
  const double width = std::ceil(cells_needed.x()) + 1, height = std::ceil(cells_needed.y()) + 1;
  if (width * height > static_cast<double>(options.max_cells)) {
    return Status::Error("grid of " + std::to_string(static_cast<int64_t>(width)) + " x " +
                         std::to_string(static_cast<int64_t>(height)) +
                         " cells exceeds max_cells; check the scan poses");
  }
  OccupancyGrid grid =
      OccupancyGrid::Filled(res, static_cast<int>(width), static_cast<int>(height), origin);
  LogOddsGrid log_odds(grid, options);

  // Pass 2: scans oldest first, so that with clamped log-odds the latest observations of a cell
  // decide it (furniture moved since an earlier session is erased by the scans that see it gone);
  // per scan, hits first (they win over the free rays of the same scan), then free rays.
  std::vector<std::size_t> order(scans.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return scans[a].scan.stamp_s < scans[b].scan.stamp_s;
  });
  std::vector<Eigen::Vector2i> end_cells;
  std::vector<char> end_is_hit;
  int32_t scan_id = 0;
  for (const std::size_t k : order) {
    if (!usable[k]) continue;
    ++scan_id;
    const PosedScan& posed = scans[k];
    const Eigen::Vector2d sensor = posed.map_T_laser.translation();
    const Eigen::Vector2i sensor_cell = grid.WorldToCell(sensor);
    end_cells.clear();
    end_is_hit.clear();
    for (std::size_t i = 0; i < posed.scan.ranges.size(); ++i) {
      const Beam beam = ClassifyBeam(posed.scan, posed.scan.ranges[i], options);
      if (!beam.used) continue;
      const double angle = posed.map_T_laser.theta() + posed.scan.BeamAngle(i);
      end_cells.push_back(grid.WorldToCell(
          sensor + beam.length_m * Eigen::Vector2d(std::cos(angle), std::sin(angle))));
      end_is_hit.push_back(beam.hit);
      if (beam.hit)
        log_odds.Update(end_cells.back().x(), end_cells.back().y(), scan_id, options.log_odds_hit);
    }
    for (std::size_t b = 0; b < end_cells.size(); ++b) {
      log_odds.TraceFree(sensor_cell.x(), sensor_cell.y(), end_cells[b].x(), end_cells[b].y(),
                         scan_id);
      // A no-return beam's last cell is free as well.
      if (!end_is_hit[b]) {
        log_odds.Update(end_cells[b].x(), end_cells[b].y(), scan_id, options.log_odds_miss);
      }
    }
    s.beams_cast += static_cast<int64_t>(end_cells.size());
  }
  log_odds.WriteInto(grid);
  return grid;
}

}  // namespace longterm_mapper2d
