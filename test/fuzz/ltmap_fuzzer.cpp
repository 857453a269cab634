// Fuzzes ParseSessionMap (binary .ltmap). Corrupt input must give an error, never a crash, UB or a
// huge allocation. Random bytes almost never carry the right payload size and CRC-32, so each
// input is parsed twice: as given, and with the header's size and checksum fixed up to match the
// payload, which lets the fuzzer reach the payload parser. A map that parses must keep the
// format's promise that serialising a parsed version-2 file gives the same bytes (version-1 files
// are upgraded, so for them serialise-parse-serialise must be stable), and its edges and gauge
// must refer to existing nodes.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "longterm_mapper2d/core/io/binary_io.h"
#include "longterm_mapper2d/core/map/session_map_file.h"

namespace longterm_mapper2d {
namespace {

constexpr std::size_t kHeaderBytes = 8 + 4 + 8 + 4;  // magic, version, payload size, CRC-32

void Check(bool condition) {
  if (!condition) __builtin_trap();
}

void FuzzOne(const std::string& bytes) {
  const StatusOr<SessionMap> map = ParseSessionMap(bytes, "fuzz.ltmap");
  if (!map.ok()) {
    Check(!map.status().message().empty());
    return;
  }
  for (const GraphEdge& edge : map->edges) {
    Check(map->nodes.count(edge.from) && map->nodes.count(edge.to));
  }
  Check(map->nodes.empty() || map->nodes.count(map->gauge));
  const std::string serialised = SerializeSessionMap(*map);
  std::uint32_t version = 0;
  std::memcpy(&version, bytes.data() + 8, sizeof(version));
  if (version == kSessionMapVersion) Check(serialised == bytes);
  const StatusOr<SessionMap> again = ParseSessionMap(serialised, "again.ltmap");
  Check(again.ok());
  Check(SerializeSessionMap(*again) == serialised);
}

// Makes the header's payload size and checksum match the bytes that follow it.
std::string WithValidChecksum(std::string bytes) {
  const std::uint64_t payload_size = bytes.size() - kHeaderBytes;
  const std::uint32_t crc = Crc32(bytes.data() + kHeaderBytes, payload_size);
  std::memcpy(&bytes[12], &payload_size, sizeof(payload_size));
  std::memcpy(&bytes[20], &crc, sizeof(crc));
  return bytes;
}

}  // namespace
}  // namespace longterm_mapper2d

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  longterm_mapper2d::FuzzOne(bytes);
  if (size >= longterm_mapper2d::kHeaderBytes) {
    longterm_mapper2d::FuzzOne(longterm_mapper2d::WithValidChecksum(bytes));
  }
  return 0;
}
