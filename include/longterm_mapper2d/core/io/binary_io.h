#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

#include "longterm_mapper2d/core/common/status.h"

namespace longterm_mapper2d {

// CRC-32 (IEEE 802.3, reflected, as zlib and PNG use it) of a byte range.
std::uint32_t Crc32(const void* data, std::size_t size, std::uint32_t crc = 0);

// Appends fixed-width little-endian values to a byte string. The session map file is built with
// it so that the bytes depend only on the values (load then save gives the same file).
class BinaryWriter {
 public:
  template <typename T>
  void Write(T value) {
    static_assert(std::is_arithmetic_v<T>, "only numbers are written raw");
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));  // the supported platforms are little-endian
    buffer_.append(bytes, sizeof(T));
  }
  void WriteString(const std::string& text) {
    Write<std::uint32_t>(static_cast<std::uint32_t>(text.size()));
    buffer_.append(text);
  }
  void WriteBytes(const std::string& bytes) { buffer_.append(bytes); }

  const std::string& bytes() const { return buffer_; }
  std::string&& TakeBytes() { return std::move(buffer_); }

 private:
  std::string buffer_;
};

// Reads what BinaryWriter wrote, never past the end: a short or corrupt input makes every later
// read fail and `status()` say where, instead of reading garbage or crashing.
class BinaryReader {
 public:
  BinaryReader(const char* data, std::size_t size) : data_(data), size_(size) {}
  explicit BinaryReader(const std::string& bytes) : BinaryReader(bytes.data(), bytes.size()) {}

  template <typename T>
  bool Read(T& value, const char* what) {
    static_assert(std::is_arithmetic_v<T>, "only numbers are read raw");
    if (!Require(sizeof(T), what)) return false;
    std::memcpy(&value, data_ + offset_, sizeof(T));
    offset_ += sizeof(T);
    return true;
  }
  // Reads a length-prefixed string of at most max_size bytes.
  bool ReadString(std::string& text, std::size_t max_size, const char* what);
  // Reads a count and checks that `count * min_bytes_each` bytes can still follow, so that a
  // corrupt count (say 10^9 nodes) fails here instead of allocating.
  bool ReadCount(std::uint64_t& count, std::size_t min_bytes_each, const char* what);

  bool ok() const { return status_.ok(); }
  const Status& status() const { return status_; }
  std::size_t offset() const { return offset_; }
  std::size_t remaining() const { return size_ - offset_; }
  void Fail(const std::string& message);

 private:
  bool Require(std::size_t bytes, const char* what);

  const char* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
  Status status_;
};

}  // namespace longterm_mapper2d
