#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace longterm_mapper2d {

// Builds one JSON object, keys in insertion order (stats files and --json outputs). Numbers that
// are not finite are written as null, since JSON has no NaN.
class JsonObject {
 public:
  JsonObject& Add(const std::string& key, double value);
  JsonObject& Add(const std::string& key, std::int64_t value);
  JsonObject& Add(const std::string& key, std::uint64_t value);
  JsonObject& Add(const std::string& key, int value) { return Add(key, std::int64_t{value}); }
  JsonObject& Add(const std::string& key, bool value);
  JsonObject& Add(const std::string& key, const std::string& value);
  JsonObject& Add(const std::string& key, const char* value) { return Add(key, std::string(value)); }
  JsonObject& Add(const std::string& key, const JsonObject& value);
  JsonObject& Add(const std::string& key, const std::vector<std::string>& values);

  // Pretty-printed with two-space indentation at the given depth.
  std::string ToString(int indent = 0) const;

 private:
  struct Member {
    std::string key;
    std::string raw;                     // a JSON value, or empty for a nested object
    std::shared_ptr<JsonObject> nested;  // set for nested objects
  };
  JsonObject& AddRaw(const std::string& key, std::string raw);
  std::vector<Member> members_;
};

std::string JsonEscape(const std::string& text);

}  // namespace longterm_mapper2d
