#include "longterm_mapper2d/core/io/map_image_io.h"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <cstdio>

#include "longterm_mapper2d/core/io/atomic_file.h"

namespace longterm_mapper2d {
namespace {

constexpr uint8_t kPixelOccupied = 0;
constexpr uint8_t kPixelFree = 254;
constexpr uint8_t kPixelUnknown = 205;

std::string Directory(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::string BaseName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// "dir/name.yaml" -> "dir/name.pgm"; other names get ".pgm" appended.
std::string ImagePathFor(const std::string& yaml_path) {
  for (const std::string ext : {".yaml", ".yml"}) {
    if (yaml_path.size() > ext.size() &&
        yaml_path.compare(yaml_path.size() - ext.size(), ext.size(), ext) == 0) {
      return yaml_path.substr(0, yaml_path.size() - ext.size()) + ".pgm";
    }
  }
  return yaml_path + ".pgm";
}

// map_saver: a cell is written occupied at or above the occupied threshold, free at or below the
// free threshold (in percent), and unknown in between, so that map_server reads it back the same.
uint8_t CellToPixel(int8_t cell, const MapImageThresholds& t) {
  if (cell < 0) return kPixelUnknown;
  if (cell >= std::lround(t.occupied_thresh * 100.0)) return kPixelOccupied;
  if (cell < t.free_thresh * 100.0) return kPixelFree;
  return kPixelUnknown;
}

// A PGM header token, skipping whitespace and '#' comments. Returns false at end of data.
bool NextHeaderToken(const std::string& data, std::size_t& pos, std::string& token) {
  token.clear();
  while (pos < data.size()) {
    const char c = data[pos];
    if (c == '#') {
      while (pos < data.size() && data[pos] != '\n') ++pos;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++pos;
    } else {
      break;
    }
  }
  while (pos < data.size() && !std::isspace(static_cast<unsigned char>(data[pos])) &&
         data[pos] != '#') {
    token += data[pos++];
  }
  return !token.empty();
}

bool ParsePositiveInt(const std::string& token, int& value) {
  if (token.empty() || token.size() > 9) return false;
  for (const char c : token) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  value = std::stoi(token);
  return value > 0;
}

struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;  // top row first, scaled to 0..255
};

StatusOr<GrayImage> ReadPgm(const std::string& path) {
  StatusOr<std::string> data = ReadFileBytes(path);
  if (!data.ok()) return data.status();
  const std::string& bytes = *data;
  std::size_t pos = 0;
  std::string magic, w, h, maxval_token;
  if (!NextHeaderToken(bytes, pos, magic) || magic != "P5") {
    return Status::Error(path + ": not a binary PGM image (expected magic 'P5', got '" +
                         magic.substr(0, 8) + "')");
  }
  GrayImage image;
  int maxval = 0;
  if (!NextHeaderToken(bytes, pos, w) || !ParsePositiveInt(w, image.width) ||
      !NextHeaderToken(bytes, pos, h) || !ParsePositiveInt(h, image.height) ||
      !NextHeaderToken(bytes, pos, maxval_token) || !ParsePositiveInt(maxval_token, maxval)) {
    return Status::Error(path + ": malformed PGM header (width, height, maxval)");
  }
  if (maxval > 255) {
    return Status::Error(path + ": 16-bit PGM (maxval " + std::to_string(maxval) +
                         ") is not supported");
  }
  // Exactly one whitespace character separates the header from the raster.
  if (pos >= bytes.size() || !std::isspace(static_cast<unsigned char>(bytes[pos]))) {
    return Status::Error(path + ": malformed PGM header");
  }
  ++pos;
  const std::size_t count = static_cast<std::size_t>(image.width) * image.height;
  if (bytes.size() - pos < count) {
    return Status::Error(path + ": truncated PGM raster (" + std::to_string(bytes.size() - pos) +
                         " of " + std::to_string(count) + " bytes)");
  }
  image.pixels.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const int raw = static_cast<uint8_t>(bytes[pos + i]);
    if (raw > maxval) {
      return Status::Error(path + ": pixel value " + std::to_string(raw) + " above maxval");
    }
    image.pixels[i] = static_cast<uint8_t>(maxval == 255 ? raw : (raw * 255 + maxval / 2) / maxval);
  }
  return image;
}

std::string MarkText(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.line >= 0 ? std::to_string(mark.line + 1) : std::string("?");
}

}  // namespace

Status WriteMapPgmYaml(const OccupancyGrid& grid, const std::string& yaml_path) {
  if (Status s = grid.Validate(); !s.ok()) return Status::Error("cannot save map: " + s.message());
  if (grid.width == 0 || grid.height == 0) return Status::Error("cannot save an empty map");
  const MapImageThresholds thresholds;
  const std::string image_path = ImagePathFor(yaml_path);

  std::string pgm =
      "P5\n" + std::to_string(grid.width) + " " + std::to_string(grid.height) + "\n255\n";
  const std::size_t header_size = pgm.size();
  pgm.resize(header_size + grid.cells.size());
  for (int row = 0; row < grid.height; ++row) {
    const int iy = grid.height - 1 - row;  // the image starts with the top row
    for (int ix = 0; ix < grid.width; ++ix) {
      pgm[header_size + static_cast<std::size_t>(row) * grid.width + ix] =
          static_cast<char>(CellToPixel(grid.at(ix, iy), thresholds));
    }
  }

  char yaml[512];
  std::snprintf(yaml, sizeof(yaml),
                "image: %s\nresolution: %.9g\norigin: [%.9g, %.9g, 0.0]\nnegate: 0\n"
                "occupied_thresh: %.3g\nfree_thresh: %.3g\n",
                BaseName(image_path).c_str(), grid.resolution_m, grid.origin_m.x(),
                grid.origin_m.y(), thresholds.occupied_thresh, thresholds.free_thresh);
  if (Status s = WriteFileAtomically(image_path, pgm); !s.ok()) return s;
  return WriteFileAtomically(yaml_path, yaml);
}

StatusOr<OccupancyGrid> ReadMapPgmYaml(const std::string& yaml_path) {
  StatusOr<std::string> text = ReadFileBytes(yaml_path);
  if (!text.ok()) return text.status();
  YAML::Node root;
  try {
    root = YAML::Load(*text);
  } catch (const YAML::Exception& e) {
    return Status::Error(yaml_path + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (!root.IsMap()) return Status::Error(yaml_path + ": expected a YAML map");

  std::string image_name, mode = "trinary";
  double resolution = 0.0, occupied_thresh = 0.65, free_thresh = 0.196;
  std::vector<double> origin;
  int negate = 0;
  // Reads one key; a missing required key or a value of the wrong type is an error with the line.
  auto read = [&](const char* key, auto& value, bool required) -> Status {
    const YAML::Node node = root[key];
    if (!node.IsDefined() || node.IsNull()) {
      return required ? Status::Error(yaml_path + ": missing key '" + key + "'") : Status::Ok();
    }
    try {
      value = node.as<std::decay_t<decltype(value)>>();
    } catch (const YAML::Exception&) {
      return Status::Error(yaml_path + ":" + MarkText(node) + ": cannot read '" + key + "'");
    }
    return Status::Ok();
  };
  for (Status s : {read("image", image_name, true), read("resolution", resolution, true),
                   read("origin", origin, true), read("negate", negate, false),
                   read("occupied_thresh", occupied_thresh, false),
                   read("free_thresh", free_thresh, false), read("mode", mode, false)}) {
    if (!s.ok()) return s;
  }
  const std::string where = yaml_path + ":" + MarkText(root["origin"]);
  if (origin.size() != 3 || !std::isfinite(origin[0]) || !std::isfinite(origin[1]) ||
      !std::isfinite(origin[2])) {
    return Status::Error(where + ": origin must be [x, y, yaw] with finite values");
  }
  if (std::abs(origin[2]) > 1e-9) {
    return Status::Error(where + ": rotated map origins (yaw != 0) are not supported");
  }
  if (!(resolution > 0.0) || !std::isfinite(resolution)) {
    return Status::Error(yaml_path + ":" + MarkText(root["resolution"]) +
                         ": resolution must be positive");
  }
  if (!(free_thresh >= 0.0 && free_thresh < occupied_thresh && occupied_thresh <= 1.0)) {
    return Status::Error(yaml_path +
                         ": thresholds must satisfy 0 <= free_thresh < "
                         "occupied_thresh <= 1");
  }
  if (mode != "trinary" && mode != "scale" && mode != "raw") {
    return Status::Error(yaml_path + ":" + MarkText(root["mode"]) + ": unknown mode '" + mode +
                         "' (trinary, scale or raw)");
  }

  const std::string image_path =
      !image_name.empty() && image_name[0] == '/' ? image_name : Directory(yaml_path) + image_name;
  StatusOr<GrayImage> image = ReadPgm(image_path);
  if (!image.ok()) return image.status();

  OccupancyGrid grid = OccupancyGrid::Filled(resolution, image->width, image->height,
                                             Eigen::Vector2d(origin[0], origin[1]));
  for (int row = 0; row < image->height; ++row) {
    const int iy = image->height - 1 - row;
    for (int ix = 0; ix < image->width; ++ix) {
      int pixel = image->pixels[static_cast<std::size_t>(row) * image->width + ix];
      if (negate) pixel = 255 - pixel;
      int8_t value;
      if (mode == "raw") {
        value = pixel > 100 ? OccupancyGrid::kUnknown : static_cast<int8_t>(pixel);
      } else {
        const double occ = (255.0 - pixel) / 255.0;
        if (occ > occupied_thresh) {
          value = OccupancyGrid::kOccupied;
        } else if (occ < free_thresh) {
          value = OccupancyGrid::kFree;
        } else if (mode == "trinary") {
          value = OccupancyGrid::kUnknown;
        } else {
          const double ratio = (occ - free_thresh) / (occupied_thresh - free_thresh);
          value = static_cast<int8_t>(1 + std::lround(98.0 * ratio));
        }
      }
      grid.at(ix, iy) = value;
    }
  }
  return grid;
}

}  // namespace longterm_mapper2d
