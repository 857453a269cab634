#include "longterm_mapper2d/core/io/binary_io.h"

#include <gtest/gtest.h>

namespace longterm_mapper2d {
namespace {

TEST(Crc32, MatchesTheStandardCheckValue) {
  const std::string text = "123456789";
  EXPECT_EQ(Crc32(text.data(), text.size()), 0xCBF43926u);
  // Incremental use gives the same result as one call.
  const std::uint32_t first = Crc32(text.data(), 4);
  EXPECT_EQ(Crc32(text.data() + 4, text.size() - 4, first), 0xCBF43926u);
}

TEST(BinaryIo, RoundTripsNumbersAndStrings) {
  BinaryWriter writer;
  writer.Write<std::uint32_t>(7);
  writer.Write<double>(-2.5);
  writer.WriteString("session");
  writer.Write<std::int64_t>(-42);
  BinaryReader reader(writer.bytes());
  std::uint32_t a = 0;
  double b = 0;
  std::string c;
  std::int64_t d = 0;
  ASSERT_TRUE(reader.Read(a, "a"));
  ASSERT_TRUE(reader.Read(b, "b"));
  ASSERT_TRUE(reader.ReadString(c, 100, "c"));
  ASSERT_TRUE(reader.Read(d, "d"));
  EXPECT_EQ(a, 7u);
  EXPECT_EQ(b, -2.5);
  EXPECT_EQ(c, "session");
  EXPECT_EQ(d, -42);
  EXPECT_EQ(reader.remaining(), 0u);
}

TEST(BinaryIo, TruncationFailsEveryLaterReadWithTheReason) {
  BinaryWriter writer;
  writer.Write<double>(1.0);
  const std::string bytes = writer.bytes().substr(0, 5);
  BinaryReader reader(bytes);
  double value = 0;
  EXPECT_FALSE(reader.Read(value, "the node pose"));
  EXPECT_FALSE(reader.ok());
  EXPECT_NE(reader.status().message().find("truncated while reading the node pose"),
            std::string::npos);
  std::uint8_t byte = 0;
  EXPECT_FALSE(reader.Read(byte, "anything"));
}

TEST(BinaryIo, ImplausibleCountsAreRefusedBeforeAllocating) {
  BinaryWriter writer;
  writer.Write<std::uint64_t>(1000000000ull);  // a header claiming 10^9 nodes
  writer.Write<double>(0.0);
  BinaryReader reader(writer.bytes());
  std::uint64_t count = 0;
  EXPECT_FALSE(reader.ReadCount(count, 24, "nodes"));
  EXPECT_NE(reader.status().message().find("implausible count"), std::string::npos);

  BinaryWriter strings;
  strings.Write<std::uint32_t>(4000000000u);
  BinaryReader string_reader(strings.bytes());
  std::string text;
  EXPECT_FALSE(string_reader.ReadString(text, 1024, "frame id"));
}

}  // namespace
}  // namespace longterm_mapper2d
