#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/map/occupancy_grid.h"

namespace longterm_mapper2d {

// An 8-bit RGB image, rows from the top, 3 bytes per pixel.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;

  static RgbImage Filled(int width, int height, uint8_t r, uint8_t g, uint8_t b);
  void Set(int col, int row, uint8_t r, uint8_t g, uint8_t b) {
    const std::size_t i = 3 * (static_cast<std::size_t>(row) * width + col);
    rgb[i] = r;
    rgb[i + 1] = g;
    rgb[i + 2] = b;
  }
};

// Thresholds of the map_server YAML; the writer uses the map_saver conventions.
struct MapImageThresholds {
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
};

// Writes a map_server-compatible pair: `yaml_path` and, beside it, the image with the same stem
// and the extension .pgm (binary P5, top row first). Pixel values: 0 occupied (cell >= 65),
// 254 free (cell <= 19), 205 unknown or uncertain. The YAML holds image (relative), resolution,
// origin [x, y, 0], negate 0, occupied_thresh 0.65, free_thresh 0.196. Both files are written
// atomically; on error neither existing file is left half-written.
Status WriteMapPgmYaml(const OccupancyGrid& grid, const std::string& yaml_path);

// Reads a map_server YAML + image pair (the image must be a binary PGM, P5, maxval <= 255; its
// path may be relative to the YAML file). Modes trinary (default), scale and raw and the negate
// flag follow map_server: occ = (255 - pixel) / 255 (or pixel / 255 when negated); occ >
// occupied_thresh gives 100, occ < free_thresh gives 0, otherwise -1 (trinary) or a scaled value.
// Errors name the file and, for YAML problems, the line.
StatusOr<OccupancyGrid> ReadMapPgmYaml(const std::string& yaml_path);

// Renders a grid for viewing: unknown grey (205), occupancy 0..100 from white (254) to black,
// the top image row being the top grid row (largest y).
RgbImage GridToImage(const OccupancyGrid& grid);

// Encodes an RGB image as PNG with libpng and writes it atomically.
Status WritePng(const RgbImage& image, const std::string& path);

// GridToImage + WritePng.
Status WriteGridPng(const OccupancyGrid& grid, const std::string& path);

}  // namespace longterm_mapper2d
