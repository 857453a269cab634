#include "longterm_mapper2d/core/io/number_table.h"

#include <gtest/gtest.h>

namespace longterm_mapper2d {
namespace {

TEST(NumberTable, SkipsCommentsAndBlankLinesAndKeepsLineNumbers) {
  const auto rows = ParseNumberTable("# a header\n\n  1 2.5 -3e2\r\n\t# indented comment\n4 5 6\n",
                                     "t.txt", 3, "'a b c'");
  ASSERT_TRUE(rows.ok()) << rows.status().message();
  ASSERT_EQ(rows->size(), 2u);
  EXPECT_EQ((*rows)[0].line_number, 3);
  EXPECT_EQ((*rows)[0].values, (std::vector<double>{1.0, 2.5, -300.0}));
  EXPECT_EQ((*rows)[1].line_number, 5);
  EXPECT_TRUE(ParseNumberTable("", "empty.txt", 3, "'a b c'")->empty());
}

TEST(NumberTable, RefusesLinesThatAreNotWholeFiniteNumbersWithTheirPlace) {
  struct Case {
    std::string text;
    std::string expected;
  };
  const Case cases[] = {
      {"1 2 3\n1 2\n", "t.txt:2: expected 3 fields 'a b c', got 2"},
      {"1 2 3 4\n", "t.txt:1: expected 3 fields 'a b c', got 4"},
      {"\n1 2 x\n", "t.txt:2: field 3 'x' is not a finite number"},
      {"1 2.5q 3\n", "t.txt:1: field 2 '2.5q'"},
      {"nan 2 3\n", "t.txt:1: field 1 'nan'"},
      {"1 -inf 3\n", "t.txt:1: field 2 '-inf'"},
      {"1 1e999 3\n", "t.txt:1: field 2 '1e999'"},
  };
  for (const Case& c : cases) {
    const auto rows = ParseNumberTable(c.text, "t.txt", 3, "'a b c'");
    ASSERT_FALSE(rows.ok()) << c.text;
    EXPECT_NE(rows.status().message().find(c.expected), std::string::npos)
        << rows.status().message();
  }
  const auto missing = ReadNumberTable("/nonexistent/t.txt", 3, "'a b c'");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("/nonexistent/t.txt"), std::string::npos);
}

TEST(NumberTable, OptionalTrailingColumnsAreAllowedPerLine) {
  const auto rows =
      ParseNumberTable("1 2\n1 2 3 4\n", "t.txt", std::vector<int>{2, 4}, "'a b [c d]'");
  ASSERT_TRUE(rows.ok()) << rows.status().message();
  ASSERT_EQ(rows->size(), 2u);
  EXPECT_EQ((*rows)[0].values.size(), 2u);
  EXPECT_EQ((*rows)[1].values.size(), 4u);
  const auto refused =
      ParseNumberTable("1 2\n1 2 3\n", "t.txt", std::vector<int>{2, 4}, "'a b [c d]'");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("t.txt:2: expected 2 or 4 fields 'a b [c d]', got 3"),
            std::string::npos)
      << refused.status().message();
}

}  // namespace
}  // namespace longterm_mapper2d
