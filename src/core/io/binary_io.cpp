#include "longterm_mapper2d/core/io/binary_io.h"

#include <array>

namespace longterm_mapper2d {
namespace {

std::array<std::uint32_t, 256> MakeCrcTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}

}  // namespace

std::uint32_t Crc32(const void* data, std::size_t size, std::uint32_t crc) {
  static const std::array<std::uint32_t, 256> kTable = MakeCrcTable();
  const auto* bytes = static_cast<const unsigned char*>(data);
  crc = ~crc;
  for (std::size_t i = 0; i < size; ++i) crc = kTable[(crc ^ bytes[i]) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

bool BinaryReader::Require(std::size_t bytes, const char* what) {
  if (!status_.ok()) return false;
  if (bytes > size_ - offset_) {
    Fail(std::string("truncated while reading ") + what);
    return false;
  }
  return true;
}

void BinaryReader::Fail(const std::string& message) {
  if (status_.ok()) {
    status_ = Status::Error(message + " (at byte " + std::to_string(offset_) + ")");
  }
}

bool BinaryReader::ReadString(std::string& text, std::size_t max_size, const char* what) {
  std::uint32_t length = 0;
  if (!Read(length, what)) return false;
  if (length > max_size) {
    Fail(std::string("implausible length ") + std::to_string(length) + " of " + what);
    return false;
  }
  if (!Require(length, what)) return false;
  text.assign(data_ + offset_, length);
  offset_ += length;
  return true;
}

bool BinaryReader::ReadCount(std::uint64_t& count, std::size_t min_bytes_each, const char* what) {
  if (!Read(count, what)) return false;
  if (min_bytes_each > 0 && count > remaining() / min_bytes_each) {
    Fail(std::string("implausible count ") + std::to_string(count) + " of " + what + " (only " +
         std::to_string(remaining()) + " bytes left)");
    return false;
  }
  return true;
}

}  // namespace longterm_mapper2d
