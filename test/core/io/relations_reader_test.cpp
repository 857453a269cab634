#include "longterm_mapper2d/core/io/relations_reader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>

namespace longterm_mapper2d {
namespace {

namespace fs = std::filesystem;

std::string WriteTemp(const std::string& text) {
  std::string path = (fs::temp_directory_path() / "ltm_relations_XXXXXX").string();
  const int fd = ::mkstemp(path.data());
  EXPECT_GE(fd, 0);
  ::close(fd);
  std::ofstream(path) << text;
  return path;
}

TEST(ReadRelations, ParsesLinesAndSkipsCommentsAndBlanks) {
  const std::string path = WriteTemp(
      "# t1 t2 x y z roll pitch yaw\n"
      "\n"
      "10.5 12.25 1.0 -2.0 0.0 0.0 0.0 0.3\n"
      "   \t\n"
      "  # indented comment\n"
      "976052905.167303 976052896.784509 -0.05699 -0.12843 0.7 0.1 0.2 -1.68221\r\n");
  const auto relations = ReadRelations(path);
  fs::remove(path);
  ASSERT_TRUE(relations.ok()) << relations.status().message();
  ASSERT_EQ(relations->size(), 2u);
  EXPECT_DOUBLE_EQ((*relations)[0].t1_s, 10.5);
  EXPECT_DOUBLE_EQ((*relations)[0].t2_s, 12.25);
  EXPECT_DOUBLE_EQ((*relations)[0].t1_T_t2.x(), 1.0);
  EXPECT_DOUBLE_EQ((*relations)[0].t1_T_t2.y(), -2.0);
  EXPECT_DOUBLE_EQ((*relations)[0].t1_T_t2.theta(), 0.3);
  // Full precision of the ipc stamps survives; t2 < t1 is allowed; z/roll/pitch are ignored.
  EXPECT_DOUBLE_EQ((*relations)[1].t1_s, 976052905.167303);
  EXPECT_DOUBLE_EQ((*relations)[1].t2_s, 976052896.784509);
  EXPECT_DOUBLE_EQ((*relations)[1].t1_T_t2.theta(), -1.68221);
}

TEST(ReadRelations, MalformedLinesNameTheLine) {
  struct Case {
    std::string text;
    std::string expected;
  };
  const Case cases[] = {
      {"1 2 0 0 0 0 0 0\n1 2 3 4 5 6 7\n", ":2: expected 8 fields"},
      {"# header\n1 2 0 0 0 0 0 0 9\n", ":2: expected 8 fields"},
      {"\n\n1 2 0 0 0 0 0 abc\n", ":3: field 8 'abc'"},
      {"1 2 0.5x 0 0 0 0 0\n", ":1: field 3 '0.5x'"},
      {"1 nan 0 0 0 0 0 0\n", ":1: field 2 'nan'"},
  };
  for (const Case& c : cases) {
    const std::string path = WriteTemp(c.text);
    const auto relations = ReadRelations(path);
    fs::remove(path);
    ASSERT_FALSE(relations.ok()) << c.text;
    EXPECT_NE(relations.status().message().find(path + c.expected), std::string::npos)
        << relations.status().message();
  }
  EXPECT_FALSE(ReadRelations("/nonexistent/file.relations").ok());
}

TEST(ReadRelations, ReadsTheIntelBenchmarkFile) {
  const std::string path = std::string(LTM_SHARED_DATA_DIR) + "/intel/intel.relations";
  if (!fs::exists(path)) GTEST_SKIP() << "skipped: no shared data at " << path;
  const auto relations = ReadRelations(path);
  ASSERT_TRUE(relations.ok()) << relations.status().message();
  EXPECT_EQ(relations->size(), 2984u);
  std::set<double> stamps;
  int backwards = 0;
  for (const Relation& r : *relations) {
    stamps.insert(r.t1_s);
    stamps.insert(r.t2_s);
    backwards += r.t2_s < r.t1_s;
  }
  EXPECT_EQ(stamps.size(), 1791u);
  EXPECT_EQ(backwards, 6);
}

}  // namespace
}  // namespace longterm_mapper2d
