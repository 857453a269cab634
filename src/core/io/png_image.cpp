// PNG encoding of RGB images and grid previews (declared in io/map_image_io.h).
#include <png.h>

#include <csetjmp>
#include <cstring>

#include "longterm_mapper2d/core/io/atomic_file.h"
#include "longterm_mapper2d/core/io/map_image_io.h"

namespace longterm_mapper2d {
namespace {

struct PngSink {
  std::string bytes;
  std::string error;
};

void AppendToSink(png_structp png, png_bytep data, png_size_t length) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  sink->bytes.append(reinterpret_cast<const char*>(data), length);
}

void FlushSink(png_structp) {}

// libpng reports errors through this handler, which must not return: it records the message
// and jumps back to the setjmp in EncodePng (no C++ objects are created between the two).
void OnPngError(png_structp png, png_const_charp message) {
  auto* sink = static_cast<PngSink*>(png_get_error_ptr(png));
  if (sink != nullptr) sink->error = message;
  png_longjmp(png, 1);
}

void OnPngWarning(png_structp, png_const_charp) {}

Status EncodePng(const RgbImage& image, const std::vector<png_bytep>& rows, PngSink& sink) {
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, &OnPngError, &OnPngWarning);
  if (png == nullptr) return Status::Error("libpng: cannot create the write structure");
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    return Status::Error("libpng: cannot create the info structure");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return Status::Error("libpng: " + sink.error);
  }
  png_set_write_fn(png, &sink, &AppendToSink, &FlushSink);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width),
               static_cast<png_uint_32>(image.height), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 6);
  png_write_info(png, info);
  png_write_image(png, const_cast<png_bytepp>(rows.data()));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return Status::Ok();
}

}  // namespace

RgbImage RgbImage::Filled(int width, int height, uint8_t r, uint8_t g, uint8_t b) {
  RgbImage image;
  image.width = width;
  image.height = height;
  image.rgb.resize(3 * static_cast<std::size_t>(width) * height);
  for (std::size_t i = 0; i < image.rgb.size(); i += 3) {
    image.rgb[i] = r;
    image.rgb[i + 1] = g;
    image.rgb[i + 2] = b;
  }
  return image;
}

RgbImage GridToImage(const OccupancyGrid& grid) {
  RgbImage image = RgbImage::Filled(grid.width, grid.height, 205, 205, 205);
  for (int iy = 0; iy < grid.height; ++iy) {
    const int row = grid.height - 1 - iy;
    for (int ix = 0; ix < grid.width; ++ix) {
      const int8_t cell = grid.at(ix, iy);
      if (cell < 0) continue;
      const int clamped = cell > 100 ? 100 : cell;
      const auto gray = static_cast<uint8_t>(254 - (clamped * 254 + 50) / 100);
      image.Set(ix, row, gray, gray, gray);
    }
  }
  return image;
}

Status WritePng(const RgbImage& image, const std::string& path) {
  if (image.width <= 0 || image.height <= 0) {
    return Status::Error("cannot write '" + path + "': the image is empty");
  }
  if (image.rgb.size() != 3 * static_cast<std::size_t>(image.width) * image.height) {
    return Status::Error("cannot write '" + path + "': the pixel buffer does not match " +
                         std::to_string(image.width) + " x " + std::to_string(image.height));
  }
  std::vector<png_bytep> rows(image.height);
  for (int r = 0; r < image.height; ++r) {
    rows[r] =
        const_cast<png_bytep>(image.rgb.data() + 3 * static_cast<std::size_t>(r) * image.width);
  }
  PngSink sink;
  if (Status s = EncodePng(image, rows, sink); !s.ok()) {
    return Status::Error("cannot write '" + path + "': " + s.message());
  }
  return WriteFileAtomically(path, sink.bytes);
}

Status WriteGridPng(const OccupancyGrid& grid, const std::string& path) {
  if (Status s = grid.Validate(); !s.ok())
    return Status::Error("cannot write '" + path + "': " + s.message());
  return WritePng(GridToImage(grid), path);
}

}  // namespace longterm_mapper2d
