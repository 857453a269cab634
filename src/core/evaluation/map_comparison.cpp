#include "longterm_mapper2d/core/evaluation/map_comparison.h"

#include <algorithm>
#include <cmath>

namespace longterm_mapper2d {
namespace {

enum CellClass : uint8_t { kUnknownClass = 0, kFreeClass = 1, kOccupiedClass = 2 };

CellClass Classify(int8_t value, int occupied_min_value) {
  if (value < 0) return kUnknownClass;
  return value >= occupied_min_value ? kOccupiedClass : kFreeClass;
}

int8_t ClassValue(uint8_t c) {
  return c == kOccupiedClass ? OccupancyGrid::kOccupied
                             : (c == kFreeClass ? OccupancyGrid::kFree : OccupancyGrid::kUnknown);
}

// Chebyshev dilation of a 0/1 mask by `radius` cells: a separable running maximum.
std::vector<uint8_t> Dilate(const std::vector<uint8_t>& mask, int width, int height, int radius) {
  if (radius <= 0) return mask;
  std::vector<uint8_t> rows(mask.size(), 0), out(mask.size(), 0);
  for (int y = 0; y < height; ++y) {
    const uint8_t* in = &mask[static_cast<std::size_t>(y) * width];
    uint8_t* o = &rows[static_cast<std::size_t>(y) * width];
    // Distance (in cells) to the last set cell seen from the left; then the same from the right.
    int last = -radius - 1;
    for (int x = 0; x < width; ++x) {
      if (in[x]) last = x;
      if (x - last <= radius) o[x] = 1;
    }
    last = width + radius;
    for (int x = width - 1; x >= 0; --x) {
      if (in[x]) last = x;
      if (last - x <= radius) o[x] = 1;
    }
  }
  for (int x = 0; x < width; ++x) {
    int last = -radius - 1;
    for (int y = 0; y < height; ++y) {
      if (rows[static_cast<std::size_t>(y) * width + x]) last = y;
      if (y - last <= radius) out[static_cast<std::size_t>(y) * width + x] = 1;
    }
    last = height + radius;
    for (int y = height - 1; y >= 0; --y) {
      if (rows[static_cast<std::size_t>(y) * width + x]) last = y;
      if (last - y <= radius) out[static_cast<std::size_t>(y) * width + x] = 1;
    }
  }
  return out;
}

double Ratio(int64_t numerator, int64_t denominator) {
  return denominator > 0 ? static_cast<double>(numerator) / denominator : 0.0;
}

}  // namespace

OccupancyGrid ResampleOntoGrid(const OccupancyGrid& source, const OccupancyGrid& frame,
                               int occupied_min_value) {
  OccupancyGrid out = OccupancyGrid::Filled(frame.resolution_m, frame.width, frame.height,
                                            frame.origin_m, OccupancyGrid::kUnknown);
  std::vector<uint8_t> best(out.cells.size(), kUnknownClass);
  // The source cell under each target centre (covers targets finer than the source).
  for (int iy = 0; iy < out.height; ++iy) {
    for (int ix = 0; ix < out.width; ++ix) {
      const Eigen::Vector2i c = source.WorldToCell(out.CellCenter(ix, iy));
      if (!source.InBounds(c.x(), c.y())) continue;
      best[out.Index(ix, iy)] = Classify(source.at(c.x(), c.y()), occupied_min_value);
    }
  }
  // Every source cell centre votes for the target cell it falls in (covers finer sources).
  for (int sy = 0; sy < source.height; ++sy) {
    for (int sx = 0; sx < source.width; ++sx) {
      const uint8_t c = Classify(source.at(sx, sy), occupied_min_value);
      if (c == kUnknownClass) continue;
      const Eigen::Vector2i t = out.WorldToCell(source.CellCenter(sx, sy));
      if (!out.InBounds(t.x(), t.y())) continue;
      uint8_t& b = best[out.Index(t.x(), t.y())];
      b = std::max(b, c);
    }
  }
  for (std::size_t i = 0; i < best.size(); ++i) out.cells[i] = ClassValue(best[i]);
  return out;
}

StatusOr<MapComparison> CompareMaps(const OccupancyGrid& map, const OccupancyGrid& truth,
                                    const MapComparisonOptions& options, RgbImage* diff) {
  OptionErrors option_errors;
  options.Validate(option_errors);
  if (!option_errors.empty())
    return Status::Error("comparison options: " + option_errors.ToString());
  if (Status s = map.Validate(); !s.ok()) return Status::Error("map: " + s.message());
  if (Status s = truth.Validate(); !s.ok()) return Status::Error("truth: " + s.message());

  // The truth lattice, grown by whole cells until it covers the map.
  const double res = truth.resolution_m;
  const Eigen::Vector2d lo = (map.origin_m - truth.origin_m) / res;
  const Eigen::Vector2d hi = (map.MaxCorner() - truth.origin_m) / res;
  const double x0 = std::min(0.0, std::floor(lo.x())), y0 = std::min(0.0, std::floor(lo.y()));
  const double x1 = std::max<double>(truth.width, std::ceil(hi.x()));
  const double y1 = std::max<double>(truth.height, std::ceil(hi.y()));
  if ((x1 - x0) * (y1 - y0) > static_cast<double>(options.max_cells)) {
    return Status::Error("the map and the truth are too far apart or too large to compare (" +
                         std::to_string(static_cast<int64_t>(x1 - x0)) + " x " +
                         std::to_string(static_cast<int64_t>(y1 - y0)) + " cells)");
  }
  const int off_x = static_cast<int>(-x0), off_y = static_cast<int>(-y0);
  const OccupancyGrid frame =
      OccupancyGrid::Filled(res, static_cast<int>(x1 - x0), static_cast<int>(y1 - y0),
                            truth.origin_m + res * Eigen::Vector2d(x0, y0));
  const int w = frame.width, h = frame.height;
  const OccupancyGrid map_on_frame = ResampleOntoGrid(map, frame, options.occupied_min_value);

  std::vector<uint8_t> truth_occ(frame.cells.size(), 0), map_occ(frame.cells.size(), 0);
  for (int iy = 0; iy < truth.height; ++iy) {
    for (int ix = 0; ix < truth.width; ++ix) {
      truth_occ[frame.Index(ix + off_x, iy + off_y)] =
          Classify(truth.at(ix, iy), options.occupied_min_value) == kOccupiedClass;
    }
  }
  for (std::size_t i = 0; i < map_occ.size(); ++i) {
    map_occ[i] = map_on_frame.cells[i] == OccupancyGrid::kOccupied;
  }
  const auto truth_near = Dilate(truth_occ, w, h, options.match_radius_cells);
  const auto truth_far = Dilate(truth_occ, w, h, options.phantom_radius_cells);
  const auto map_near = Dilate(map_occ, w, h, options.match_radius_cells);

  MapComparison result;
  if (diff != nullptr) *diff = RgbImage::Filled(w, h, 205, 205, 205);
  for (int iy = 0; iy < h; ++iy) {
    for (int ix = 0; ix < w; ++ix) {
      const std::size_t i = frame.Index(ix, iy);
      const bool observed = map_on_frame.cells[i] != OccupancyGrid::kUnknown;
      uint8_t r = observed ? 255 : 205, g = r, b = r;
      if (map_occ[i]) {
        ++result.map_occupied;
        if (truth_occ[i]) ++result.on_truth;
        if (truth_near[i]) {
          ++result.correct;
          r = 0, g = 170, b = 0;
        } else if (!truth_far[i]) {
          ++result.phantom;
          r = 255, g = 0, b = 0;
        } else {
          r = 255, g = 160, b = 0;
        }
      }
      if (truth_occ[i]) {
        ++result.truth_occupied;
        if (observed) {
          ++result.truth_observed;
          if (map_near[i]) {
            ++result.recalled;
          } else {
            r = 0, g = 0, b = 255;
          }
        } else {
          r = 150, g = 150, b = 255;
        }
      }
      if (diff != nullptr) diff->Set(ix, h - 1 - iy, r, g, b);
    }
  }
  result.precision = Ratio(result.correct, result.map_occupied);
  result.precision_on_truth = Ratio(result.on_truth, result.map_occupied);
  result.recall = Ratio(result.recalled, result.truth_observed);
  result.phantom_fraction = Ratio(result.phantom, result.map_occupied);
  return result;
}

}  // namespace longterm_mapper2d
