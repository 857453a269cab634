// Fuzzes ParseRelations (benchmark .relations text). Malformed input must give an error, never a
// crash or UB. Relations that parse feed the error metric directly, so every stamp and pose must
// be finite and every angle normalised to (-pi, pi].
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/io/relations_reader.h"

namespace longterm_mapper2d {
namespace {

void Check(bool condition) {
  if (!condition) __builtin_trap();
}

void FuzzOne(const std::string& text) {
  const StatusOr<std::vector<Relation>> relations = ParseRelations(text, "fuzz.relations");
  if (!relations.ok()) {
    Check(!relations.status().message().empty());
    return;
  }
  for (const Relation& r : *relations) {
    Check(std::isfinite(r.t1_s) && std::isfinite(r.t2_s));
    Check(r.t1_T_t2.IsFinite());
    Check(r.t1_T_t2.theta() > -M_PI && r.t1_T_t2.theta() <= M_PI);
  }
}

}  // namespace
}  // namespace longterm_mapper2d

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  longterm_mapper2d::FuzzOne(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
