#include "longterm_mapper2d/core/io/map_image_io.h"

#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "longterm_mapper2d/core/io/atomic_file.h"

namespace longterm_mapper2d {
namespace {

namespace fs = std::filesystem;

class MapImageIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "ltm_map_io_XXXXXX").string();
    ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (fs::path(dir_) / name).string(); }
  void WriteText(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name), std::ios::binary) << text;
  }
  std::string dir_;
};

// A 4 x 3 grid with every kind of value at distinct places.
OccupancyGrid MakeGrid() {
  OccupancyGrid grid = OccupancyGrid::Filled(0.1, 4, 3, Eigen::Vector2d(-1.25, 2.5));
  grid.at(0, 0) = 100;
  grid.at(1, 0) = 0;
  grid.at(3, 2) = 100;
  grid.at(2, 1) = 0;
  grid.at(1, 2) = 0;
  return grid;
}

TEST_F(MapImageIoTest, PgmYamlRoundTripKeepsCellsAndGeometry) {
  const OccupancyGrid grid = MakeGrid();
  ASSERT_TRUE(WriteMapPgmYaml(grid, Path("map.yaml")).ok());
  ASSERT_TRUE(fs::exists(Path("map.pgm")));

  // The raster is map_saver's: top row first, 0 occupied, 254 free, 205 unknown.
  StatusOr<std::string> pgm = ReadFileBytes(Path("map.pgm"));
  ASSERT_TRUE(pgm.ok());
  const std::string header = "P5\n4 3\n255\n";
  ASSERT_EQ(pgm->size(), header.size() + 12);
  EXPECT_EQ(pgm->substr(0, header.size()), header);
  const auto pixel = [&](int row, int col) {
    return static_cast<uint8_t>((*pgm)[header.size() + row * 4 + col]);
  };
  EXPECT_EQ(pixel(0, 3), 0);    // cell (3, 2)
  EXPECT_EQ(pixel(0, 1), 254);  // cell (1, 2)
  EXPECT_EQ(pixel(2, 0), 0);    // cell (0, 0)
  EXPECT_EQ(pixel(2, 1), 254);  // cell (1, 0)
  EXPECT_EQ(pixel(1, 0), 205);  // cell (0, 1) unknown

  StatusOr<OccupancyGrid> read = ReadMapPgmYaml(Path("map.yaml"));
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->width, 4);
  EXPECT_EQ(read->height, 3);
  EXPECT_NEAR(read->resolution_m, 0.1, 1e-12);
  EXPECT_NEAR(read->origin_m.x(), -1.25, 1e-9);
  EXPECT_NEAR(read->origin_m.y(), 2.5, 1e-9);
  EXPECT_EQ(read->cells, grid.cells);
}

TEST_F(MapImageIoTest, IntermediateValuesAreQuantisedLikeMapSaver) {
  OccupancyGrid grid = OccupancyGrid::Filled(0.05, 4, 1, Eigen::Vector2d::Zero());
  grid.cells = {10, 40, 70, 19};
  ASSERT_TRUE(WriteMapPgmYaml(grid, Path("q.yaml")).ok());
  StatusOr<OccupancyGrid> read = ReadMapPgmYaml(Path("q.yaml"));
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->cells, (std::vector<int8_t>{0, -1, 100, 0}));
}

TEST_F(MapImageIoTest, ReadsNegatedAndScaledMapsWithCommentsInHeader) {
  WriteText("s.pgm", std::string("P5\n# made by hand\n3 1\n255\n") + '\xff' + '\x00' + '\x80');
  WriteText("s.yaml",
            "image: s.pgm\nresolution: 0.5\norigin: [1.0, 2.0, 0.0]\nnegate: 1\nmode: scale\n");
  StatusOr<OccupancyGrid> read = ReadMapPgmYaml(Path("s.yaml"));
  ASSERT_TRUE(read.ok()) << read.status().message();
  // Negated: 255 -> occ 1 (occupied), 0 -> occ 0 (free), 128 -> occ 0.502 (scaled in between).
  EXPECT_EQ(read->at(0, 0), 100);
  EXPECT_EQ(read->at(1, 0), 0);
  EXPECT_EQ(read->at(2, 0),
            static_cast<int8_t>(1 + std::lround(98 * (128.0 / 255 - 0.196) / (0.65 - 0.196))));
}

TEST_F(MapImageIoTest, BadFilesGiveClearErrors) {
  EXPECT_FALSE(ReadMapPgmYaml(Path("absent.yaml")).ok());

  WriteText("t.pgm", std::string("P5\n4 4\n255\n") + "abc");
  WriteText("t.yaml", "image: t.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  StatusOr<OccupancyGrid> truncated = ReadMapPgmYaml(Path("t.yaml"));
  ASSERT_FALSE(truncated.ok());
  EXPECT_NE(truncated.status().message().find("truncated"), std::string::npos);

  WriteText("m.yaml", "image: t.pgm\norigin: [0, 0, 0]\n");
  StatusOr<OccupancyGrid> missing = ReadMapPgmYaml(Path("m.yaml"));
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("resolution"), std::string::npos);

  WriteText("o.yaml", "image: t.pgm\nresolution: 0.05\norigin: [0, 0]\n");
  StatusOr<OccupancyGrid> origin = ReadMapPgmYaml(Path("o.yaml"));
  ASSERT_FALSE(origin.ok());
  EXPECT_NE(origin.status().message().find("o.yaml:3:"), std::string::npos)
      << origin.status().message();

  WriteText("y.yaml", "image: t.pgm\nresolution: [0.05\n");
  StatusOr<OccupancyGrid> syntax = ReadMapPgmYaml(Path("y.yaml"));
  ASSERT_FALSE(syntax.ok());
  EXPECT_NE(syntax.status().message().find("y.yaml:"), std::string::npos);

  WriteText("a.pgm", "P2\n1 1\n255\n0\n");
  WriteText("a.yaml", "image: a.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  StatusOr<OccupancyGrid> ascii = ReadMapPgmYaml(Path("a.yaml"));
  ASSERT_FALSE(ascii.ok());
  EXPECT_NE(ascii.status().message().find("P5"), std::string::npos);
}

TEST_F(MapImageIoTest, WritesToMissingFolderFailWithoutLeftovers) {
  const Status s = WriteMapPgmYaml(MakeGrid(), Path("no/such/dir/map.yaml"));
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("no/such/dir"), std::string::npos);
  // Replacing an existing file leaves no temporary behind.
  ASSERT_TRUE(WriteFileAtomically(Path("x.txt"), "old").ok());
  ASSERT_TRUE(WriteFileAtomically(Path("x.txt"), "new").ok());
  EXPECT_EQ(*ReadFileBytes(Path("x.txt")), "new");
  int entries = 0;
  for (const auto& e : fs::directory_iterator(dir_)) entries += e.is_regular_file();
  EXPECT_EQ(entries, 1);
}

TEST_F(MapImageIoTest, PngDecodesToTheWrittenPixels) {
  RgbImage image = RgbImage::Filled(5, 2, 10, 20, 30);
  image.Set(4, 1, 255, 0, 7);
  ASSERT_TRUE(WritePng(image, Path("i.png")).ok());

  png_image decoded;
  std::memset(&decoded, 0, sizeof(decoded));
  decoded.version = PNG_IMAGE_VERSION;
  ASSERT_NE(png_image_begin_read_from_file(&decoded, Path("i.png").c_str()), 0);
  decoded.format = PNG_FORMAT_RGB;
  std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(decoded));
  ASSERT_NE(png_image_finish_read(&decoded, nullptr, pixels.data(), 0, nullptr), 0);
  EXPECT_EQ(decoded.width, 5u);
  EXPECT_EQ(decoded.height, 2u);
  EXPECT_EQ(pixels, image.rgb);

  EXPECT_FALSE(WritePng(RgbImage{}, Path("empty.png")).ok());
}

TEST(GridToImage, PutsTheTopGridRowFirst) {
  OccupancyGrid grid = OccupancyGrid::Filled(1.0, 2, 2, Eigen::Vector2d::Zero());
  grid.at(0, 1) = 100;
  grid.at(1, 1) = 0;
  const RgbImage image = GridToImage(grid);
  ASSERT_EQ(image.rgb.size(), 12u);
  EXPECT_EQ(image.rgb[0], 0);    // (0, 1) occupied, top-left pixel
  EXPECT_EQ(image.rgb[3], 254);  // (1, 1) free
  EXPECT_EQ(image.rgb[6], 205);  // (0, 0) unknown
}

}  // namespace
}  // namespace longterm_mapper2d
